#include "motionmap/core/text_cursor.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"

namespace motionmap {
namespace {

// Runs `f` on a cursor and returns the ParseError it throws (fails the test if none).
template <typename F>
ParseError error_of(std::string_view text, F f) {
  TextCursor cur(text, "t.txt");
  try {
    f(cur);
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError for: " << text;
  return ParseError("", 0, 0, "");
}

TEST(TextCursor, TokensAcrossLfCrlfAndLoneCrLineEnds) {
  TextCursor cur("a b\nc\r\nd\re\t\tf", "t.txt");
  EXPECT_EQ(cur.next_token(), "a");
  EXPECT_EQ(cur.next_token(), "b");
  EXPECT_EQ(cur.line(), 1u);
  EXPECT_EQ(cur.next_token(), "c");
  EXPECT_EQ(cur.line(), 2u);
  EXPECT_EQ(cur.next_token(), "d");
  EXPECT_EQ(cur.line(), 3u);
  EXPECT_EQ(cur.next_token(), "e");
  EXPECT_EQ(cur.line(), 4u);
  EXPECT_EQ(cur.column(), 2u);
  EXPECT_EQ(cur.next_token(), "f");
  EXPECT_EQ(cur.column(), 5u);  // tabs count as one column each
  EXPECT_EQ(cur.next_token(), "");
  EXPECT_TRUE(cur.at_end());
}

TEST(TextCursor, TokenOnLineStopsAtLineEndAndLoneCr) {
  TextCursor cur("a b \r c", "t.txt");
  EXPECT_EQ(cur.next_token_on_line(), "a");
  EXPECT_EQ(cur.next_token_on_line(), "b");
  EXPECT_EQ(cur.next_token_on_line(), "");
  cur.skip_inline_space();
  EXPECT_TRUE(cur.at_line_end());  // the lone CR is a line end
  EXPECT_TRUE(cur.consume_line_end());
  EXPECT_EQ(cur.line(), 2u);
  EXPECT_EQ(cur.next_token_on_line(), "c");
}

TEST(TextCursor, RestOfLineAndSkipLine) {
  TextCursor cur("ROOT mixamorig:Hips x\r\nnext", "t.txt");
  EXPECT_EQ(cur.next_token(), "ROOT");
  cur.skip_inline_space();
  EXPECT_EQ(cur.rest_of_line(), "mixamorig:Hips x");
  EXPECT_TRUE(cur.at_line_end());
  cur.skip_line();
  EXPECT_EQ(cur.line(), 2u);
  EXPECT_EQ(cur.next_token(), "next");
}

TEST(TextCursor, NumbersInEveryFormRealFilesUse) {
  TextCursor cur("+1.5 -0.0000 .0083333 1e-3 1E+2 5. -2.30145e-07 0.016666666666666666 7", "t");
  EXPECT_EQ(cur.next_number("n"), 1.5);
  const double negative_zero = cur.next_number("n");
  EXPECT_EQ(negative_zero, 0.0);
  EXPECT_TRUE(std::signbit(negative_zero));
  EXPECT_EQ(cur.next_number("n"), 0.0083333);
  EXPECT_EQ(cur.next_number("n"), 1e-3);
  EXPECT_EQ(cur.next_number("n"), 100.0);
  EXPECT_EQ(cur.next_number("n"), 5.0);
  EXPECT_EQ(cur.next_number("n"), -2.30145e-07);
  EXPECT_EQ(cur.next_number("n"), 0.016666666666666666);
  EXPECT_EQ(cur.next_number("n"), 7.0);
}

TEST(TextCursor, UnderflowReadsAsZeroNotAsError) {
  TextCursor cur("1e-400 -1e-400 4.9e-324", "t");
  EXPECT_EQ(cur.next_number("n"), 0.0);
  EXPECT_EQ(cur.next_number("n"), 0.0);
  EXPECT_EQ(cur.next_number("n"), 4.9e-324);
}

TEST(TextCursor, NonFiniteNumbersAreRejectedWithPosition) {
  for (const char* bad : {"nan", "inf", "-inf", "infinity", "1e999", "-1e999", "NaN"}) {
    const std::string text = std::string("1 ") + bad;
    const ParseError e = error_of(text, [](TextCursor& c) {
      c.next_number("x");
      c.next_number("x");
    });
    EXPECT_EQ(e.line(), 1u);
    EXPECT_EQ(e.column(), 3u);
    EXPECT_EQ(e.message(), "expected x (a finite number), found '" + std::string(bad) + "'");
  }
}

TEST(TextCursor, MalformedNumbersAreRejected) {
  for (const char* bad : {"+-1", "++1", "1e", "1.2.3", "abc", "0x10", "1,5", "-", "."}) {
    const ParseError e = error_of(bad, [](TextCursor& c) { c.next_number("a value"); });
    EXPECT_EQ(e.message(), "expected a value, found '" + std::string(bad) + "'") << bad;
    EXPECT_EQ(std::string(e.what()), "t.txt:1:1: error: " + e.message());
  }
}

TEST(TextCursor, SameLineNumberReportsEndOfLineAndEndOfFile) {
  ParseError e = error_of("OFFSET 1 2\r\n3", [](TextCursor& c) {
    c.next_token();
    for (int i = 0; i < 3; ++i) c.next_number("OFFSET value", true);
  });
  EXPECT_EQ(std::string(e.what()), "t.txt:1:11: error: expected OFFSET value, found end of line");
  e = error_of("1 ", [](TextCursor& c) {
    c.next_number("a", true);
    c.next_number("b", true);
  });
  EXPECT_EQ(std::string(e.what()), "t.txt:1:3: error: expected b, found end of file");
}

TEST(TextCursor, IntegersInRange) {
  TextCursor cur("+12 0 -3", "t");
  EXPECT_EQ(cur.next_integer("n", 0, 100), 12);
  EXPECT_EQ(cur.next_integer("n", 0, 100), 0);
  ParseError e = error_of("-3", [](TextCursor& c) { c.next_integer("a count", 0, 100); });
  EXPECT_EQ(e.message(), "expected a count, found '-3'");
  e = error_of("12.5", [](TextCursor& c) { c.next_integer("a count", 0, 100); });
  EXPECT_EQ(e.message(), "expected a count, found '12.5'");
  e = error_of("+-3", [](TextCursor& c) { c.next_integer("a count", -100, 100); });
  EXPECT_EQ(e.message(), "expected a count, found '+-3'");
  e = error_of("99999999999999999999999", [](TextCursor& c) { c.next_integer("n", 0, 10); });
  EXPECT_EQ(e.column(), 1u);
}

TEST(TextCursor, ExpectNamesKeywordAndQuotesGarbage) {
  ParseError e = error_of("\n  HIERARCH Y", [](TextCursor& c) { c.expect("HIERARCHY"); });
  EXPECT_EQ(std::string(e.what()), "t.txt:2:3: error: expected 'HIERARCHY', found 'HIERARCH'");
  e = error_of(std::string_view("\x01\xff\x00z", 4), [](TextCursor& c) { c.expect("HIERARCHY"); });
  EXPECT_EQ(e.message(), "expected 'HIERARCHY', found '\\x01\\xFF\\x00z'");
  e = error_of("", [](TextCursor& c) { c.expect("HIERARCHY"); });
  EXPECT_EQ(std::string(e.what()), "t.txt:1:1: error: expected 'HIERARCHY', found end of file");
}

TEST(TextCursor, MarkAndResetReturnToAnEarlierToken) {
  TextCursor cur("a\nbb cc\ndd", "t.txt");
  cur.next_token();
  cur.skip_space();
  const TextCursor::Mark m = cur.mark();
  cur.next_token();
  cur.next_token();
  cur.next_token();
  EXPECT_EQ(cur.line(), 3u);
  cur.reset(m);
  EXPECT_EQ(cur.line(), 2u);
  EXPECT_EQ(cur.column(), 1u);
  const ParseError e = error_of("", [&](TextCursor&) { cur.fail_expected("x"); });
  EXPECT_EQ(std::string(e.what()), "t.txt:2:1: error: expected x, found 'bb'");
}

TEST(TextCursor, SkipToContentPassesBlankLinesAndComments) {
  TextCursor cur("\n  # a comment\r\n\t\n# another\rkey 1 # tail\n#last", "t.txt");
  ASSERT_TRUE(cur.skip_to_content('#'));
  EXPECT_EQ(cur.line(), 5u);
  EXPECT_EQ(cur.peek_char(), 'k');
  EXPECT_EQ(cur.next_token_on_line('#'), "key");
  EXPECT_EQ(cur.next_token_on_line('#'), "1");
  EXPECT_EQ(cur.next_token_on_line('#'), "") << "a comment ends the line's tokens";
  EXPECT_TRUE(cur.at_line_end_or_comment('#'));
  EXPECT_TRUE(cur.at_line_end()) << "the comment is skipped, the line end is not";
  EXPECT_FALSE(cur.skip_to_content('#')) << "only a comment left";
  EXPECT_TRUE(cur.at_end());
  EXPECT_EQ(cur.peek_char(), '\0');
}

TEST(TextCursor, ExpectLineEndAllowsBlanksAndACommentOnly) {
  TextCursor ok("a  \t# done\nb", "t.txt");
  ok.next_token();
  ok.expect_line_end('#');
  EXPECT_EQ(ok.next_token(), "b");
  ParseError e = error_of("a b # c", [](TextCursor& c) {
    c.next_token();
    c.expect_line_end('#');
  });
  EXPECT_EQ(std::string(e.what()), "t.txt:1:3: error: expected end of line, found 'b'");
  e = error_of("a 1 2", [](TextCursor& c) {
    c.next_token();
    c.next_number("x", true);
    c.expect_line_end('#', "end of line after the value");
  });
  EXPECT_EQ(e.message(), "expected end of line after the value, found '2'");
}

TEST(TextCursor, FailExpectedAtReportsAnEarlierMarkWithASuffix) {
  const ParseError e = error_of("first\n  second third", [](TextCursor& c) {
    c.next_token();
    const TextCursor::Mark at = c.mark_next();
    EXPECT_EQ(at.line, 2u);
    c.next_token();
    EXPECT_EQ(c.mark_next_on_line().line, 2u);
    EXPECT_EQ(c.column(), 10u) << "on 'third'";
    c.next_token();
    c.fail_expected_at(at, "a keyword", " (again)");
  });
  EXPECT_EQ(std::string(e.what()), "t.txt:2:3: error: expected a keyword, found 'second' (again)");
  const ParseError end = error_of("x  \ny", [](TextCursor& c) {
    c.next_token();
    const TextCursor::Mark at = c.mark_next_on_line();
    c.next_token();
    c.fail_expected_at(at, "a value");
  });
  EXPECT_EQ(std::string(end.what()), "t.txt:1:4: error: expected a value, found end of line");
}

TEST(TextCursor, NumberOnLineBuildsItsMessageOnlyOnFailure) {
  TextCursor cur("1.5 -2e3 7", "t.txt");
  int built = 0;
  const auto what = [&] {
    ++built;
    return std::string("a value");
  };
  EXPECT_EQ(cur.next_number_on_line(what), 1.5);
  EXPECT_EQ(cur.next_number_on_line(what), -2000.0);
  EXPECT_EQ(cur.next_number_on_line(what), 7.0);
  EXPECT_EQ(built, 0);
  ParseError e = error_of("1 x", [&](TextCursor& c) {
    c.next_number_on_line(what);
    c.next_number_on_line(what);
  });
  EXPECT_EQ(std::string(e.what()), "t.txt:1:3: error: expected a value, found 'x'");
  EXPECT_EQ(built, 1);
  e = error_of("1\n2", [&](TextCursor& c) {
    c.next_number_on_line(what);
    c.next_number_on_line(what);
  });
  EXPECT_EQ(e.message(), "expected a value, found end of line");
  e = error_of("1e999", [&](TextCursor& c) { c.next_number_on_line(what); });
  EXPECT_EQ(e.message(), "expected a value (a finite number), found '1e999'");
}

TEST(TextHelpers, AsciiCaseDigitsAndTrimming) {
  EXPECT_TRUE(ascii_iequals(":FULLY-SPECIFIED", ":fully-specified"));
  EXPECT_TRUE(ascii_iequals("", ""));
  EXPECT_FALSE(ascii_iequals("deg", "degrees"));
  EXPECT_FALSE(ascii_iequals("rx", "ry"));
  EXPECT_FALSE(ascii_iequals("\xC9", "\xE9")) << "only ASCII letters fold";
  EXPECT_TRUE(all_digits("0123456789"));
  EXPECT_FALSE(all_digits(""));
  EXPECT_FALSE(all_digits("12a"));
  EXPECT_FALSE(all_digits("+1"));
  EXPECT_EQ(trim_blanks(" \t name with spaces \v\f"), "name with spaces");
  EXPECT_EQ(trim_blanks(" \t "), "");
}

TEST(TextCursor, ParseNumberLeavesPointerOnFailure) {
  const std::string s = "12abc";
  const char* p = s.data();
  double v = 0.0;
  EXPECT_EQ(parse_number(p, s.data() + s.size(), v), NumberStatus::NotANumber);
  EXPECT_EQ(p, s.data());
  const std::string t = "-7.25\t";
  p = t.data();
  EXPECT_EQ(parse_number(p, t.data() + t.size(), v), NumberStatus::Ok);
  EXPECT_EQ(v, -7.25);
  EXPECT_EQ(*p, '\t');
}

}  // namespace
}  // namespace motionmap
