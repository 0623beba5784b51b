#pragma once
// A cursor over a whole text file for hand-written parsers: whitespace-separated tokens, numbers
// through std::from_chars, and the 1-based line and column of everything it reads, so every
// failure becomes `path:line:col: error: expected <what>, found '<token>'`.
// Line ends may be LF, CRLF or lone CR; tabs count as one column. Line-oriented formats with
// comments (ASF, AMC: `#` to the end of the line) use the members that take a comment character.
//
//   TextCursor c(text, path);
//   while (c.skip_to_content('#')) {
//     const TextCursor::Mark at = c.mark_next();
//     const std::string_view key = c.next_token();
//     if (!ascii_iequals(key, "length")) c.fail_expected_at(at, "'length'");
//     const double length = c.next_number("a length", /*same_line=*/true);
//     c.expect_line_end('#');
//   }
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace motionmap {

class TextCursor {
 public:
  TextCursor(std::string_view text, std::string path);

  /// Skips spaces, tabs and line ends.
  void skip_space();
  /// Skips spaces, tabs, \v and \f, but not line ends (LF, CR).
  void skip_inline_space();
  /// Consumes one line end (LF, CRLF or CR) if the cursor is on one; returns whether it did.
  bool consume_line_end();
  /// Skips the rest of the current line including its line end.
  void skip_line();
  /// The rest of the current line without its line end, consumed (the cursor ends on the line end).
  std::string_view rest_of_line();

  bool at_end() const { return m_pos >= m_text.size(); }
  /// After skip_inline_space(): true at a line end or the end of the text.
  bool at_line_end() const;

  /// The next whitespace-delimited token after skipping whitespace (incl. line ends); not consumed.
  std::string_view peek_token();
  /// Consumes and returns the next token (after skipping whitespace incl. line ends). Empty at end.
  std::string_view next_token();
  /// Like next_token but never crosses a line end: empty if the line has no more tokens.
  std::string_view next_token_on_line();

  /// Like next_token_on_line(), but a token starting with `comment` starts a comment, which ends
  /// the line's tokens: empty then (the comment is not consumed).
  std::string_view next_token_on_line(char comment);

  /// The next character, not consumed; '\0' at the end of the text.
  char peek_char() const { return at_end() ? '\0' : m_text[m_pos]; }
  /// Skips whitespace, line ends and comments (from `comment` to the end of its line), so the
  /// cursor is on the next token. Returns false if only those were left (at the end of the text).
  bool skip_to_content(char comment);
  /// Skips blanks and a comment on the current line; returns whether nothing else is left on it
  /// (the cursor is then on the line end or at the end of the text).
  bool at_line_end_or_comment(char comment);
  /// Requires that only blanks and a comment are left on the current line, and skips them.
  /// @throws ParseError `expected <what>, found '<token>'` otherwise.
  void expect_line_end(char comment, std::string_view what = "end of line");

  /// Consumes the next token, which must equal `keyword`. @throws ParseError otherwise.
  void expect(std::string_view keyword);
  /// Consumes a finite floating-point number (optionally on the current line only).
  /// @throws ParseError naming `what` if the token is not a complete finite number.
  double next_number(std::string_view what, bool same_line = false);
  /// Consumes an integer token in [min, max]. @throws ParseError otherwise.
  long long next_integer(std::string_view what, long long min, long long max,
                         bool same_line = false);
  /// next_number(what(), true) for the loops over a file's values: `what` (a callable returning
  /// the description as a std::string) is only called when the token is not a finite number, to
  /// build the message. @throws ParseError as next_number().
  template <typename What>
  double next_number_on_line(const What& what);

  /// Throws `path:line:col: error: expected <expected>, found '<found>'` at the start of the next
  /// token (or the end of file / line end).
  [[noreturn]] void fail_expected(std::string_view expected);
  /// Throws `path:line:col: error: <message>` at the given position.
  [[noreturn]] void fail_at(std::size_t line, std::size_t column, const std::string& message) const;

  std::size_t line() const { return m_line; }
  std::size_t column() const { return m_pos - m_line_start + 1; }
  std::size_t position() const { return m_pos; }
  std::size_t remaining() const { return m_text.size() - m_pos; }
  const std::string& path() const { return m_path; }
  std::string_view text() const { return m_text; }

  /// Describes the upcoming token for a message: the token quoted, "end of line" or "end of file".
  std::string describe_next();

  /// A saved position, to come back to (e.g. to report an error at a token already consumed).
  struct Mark {
    std::size_t pos = 0;
    std::size_t line = 1;
    std::size_t line_start = 0;
  };
  Mark mark() const { return {m_pos, m_line, m_line_start}; }
  /// Moves to `m`, a mark of this cursor (fast parsers that scan text() themselves report their
  /// position back this way).
  void reset(const Mark& m) {
    m_pos = m.pos;
    m_line = m.line;
    m_line_start = m.line_start;
  }
  /// Skips whitespace (incl. line ends) and marks where the next token starts.
  Mark mark_next() {
    skip_space();
    return mark();
  }
  /// Skips blanks and marks where the next token on the line (or the line end) is.
  Mark mark_next_on_line() {
    skip_inline_space();
    return mark();
  }
  /// Throws `path:line:col: error: expected <expected>, found <what is at `at`><suffix>` at `at`,
  /// a mark of this cursor: for a token that is judged only after it has been read.
  [[noreturn]] void fail_expected_at(const Mark& at, std::string_view expected,
                                     std::string_view suffix = {});

 private:
  std::string_view m_text;
  std::string m_path;
  std::size_t m_pos = 0;
  std::size_t m_line = 1;
  std::size_t m_line_start = 0;
};

/// Space, tab, \v or \f (not a line end).
inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}
/// A blank or a line end.
inline bool is_space(char c) {
  return is_blank(c) || c == '\n' || c == '\r';
}

/// A comma-separated field of a CSV line: its text without surrounding blanks, and the 1-based
/// column where that text starts.
struct CsvField {
  std::string_view text;
  std::size_t column = 1;
};

/// The fields of one CSV line (no quoting: the files MotionMap reads hold numbers and names).
std::vector<CsvField> split_csv_fields(std::string_view row);

/// A CSV row: its 1-based line, its text without the line end, and its fields.
struct CsvRow {
  std::size_t line = 0;
  std::string_view text;
  std::vector<CsvField> fields;
};

/// Moves `cur` past the next row that is neither blank nor a '#' comment (and its line end) and
/// returns it in `row`; false at the end of the text.
bool next_csv_row(TextCursor& cur, CsvRow& row);

/// `text` without a leading UTF-8 byte-order mark (spreadsheets write one).
inline std::string_view skip_utf8_bom(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

/// ASCII lower case (other bytes as they are, whatever the locale), for case-insensitive names.
std::string ascii_lower(std::string_view s);

/// Whether `a` and `b` are equal ignoring ASCII case, for case-insensitive keywords (other bytes
/// must match exactly, whatever the locale).
bool ascii_iequals(std::string_view a, std::string_view b);

/// Whether `s` is non-empty and made of the ASCII digits 0-9 only.
inline bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (const char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

/// `s` without leading and trailing blanks (see is_blank()).
inline std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

enum class NumberStatus { Ok, NotANumber, NotFinite };

/// Parses the number starting at `first` (strtod syntax plus a leading '+', '.5' and '5.' forms;
/// no leading whitespace), which must end at whitespace or `last`. On Ok, `value` is set and
/// `first` moves past the number; otherwise `first` is unchanged. Values that underflow are read as
/// the nearest double (0 or subnormal); nan, inf and values beyond the double range are NotFinite.
/// Inline because the motion-block loops of the readers call it once per value.
inline NumberStatus parse_number(const char*& first, const char* last, double& value) {
  const char* start = first;
  if (start != last && *start == '+') {
    ++start;  // from_chars rejects '+', strtod accepts it; but not "+-1"
    if (start != last && (*start == '-' || *start == '+')) return NumberStatus::NotANumber;
  }
  auto [ptr, ec] = std::from_chars(start, last, value);
  if (ec == std::errc::result_out_of_range) {
    // Retry in the wider type to tell underflow (a valid, tiny number) from overflow.
    long double wide = 0.0L;
    const auto r = std::from_chars(start, last, wide);
    ptr = r.ptr;
    ec = r.ec;
    value = static_cast<double>(wide);
  } else if (ec != std::errc()) {
    return NumberStatus::NotANumber;
  }
  if (ptr != last && !is_space(*ptr)) return NumberStatus::NotANumber;
  if (ec != std::errc() || !std::isfinite(value)) return NumberStatus::NotFinite;
  first = ptr;
  return NumberStatus::Ok;
}

template <typename What>
double TextCursor::next_number_on_line(const What& what) {
  skip_inline_space();
  const char* first = m_text.data() + m_pos;
  double value = 0.0;
  if (!at_line_end() &&
      parse_number(first, m_text.data() + m_text.size(), value) == NumberStatus::Ok) {
    m_pos = static_cast<std::size_t>(first - m_text.data());  // a number spans no line end
    return value;
  }
  return next_number(what(), true);  // throws the full message
}

}  // namespace motionmap
