#include "motionmap/core/text_cursor.h"

#include <charconv>
#include <cmath>

#include "motionmap/core/error.h"

namespace motionmap {

TextCursor::TextCursor(std::string_view text, std::string path)
    : m_text(text), m_path(std::move(path)) {}

bool TextCursor::consume_line_end() {
  if (at_end()) return false;
  if (m_text[m_pos] == '\r') {
    ++m_pos;
    if (m_pos < m_text.size() && m_text[m_pos] == '\n') ++m_pos;
  } else if (m_text[m_pos] == '\n') {
    ++m_pos;
  } else {
    return false;
  }
  ++m_line;
  m_line_start = m_pos;
  return true;
}

void TextCursor::skip_space() {
  while (!at_end()) {
    const char c = m_text[m_pos];
    if (is_blank(c)) {
      ++m_pos;
    } else if (c == '\n' || c == '\r') {
      consume_line_end();
    } else {
      break;
    }
  }
}

void TextCursor::skip_inline_space() {
  // A CR, lone (classic Mac files) or before LF, is a line end: stop there.
  while (!at_end() && is_blank(m_text[m_pos])) ++m_pos;
}

bool TextCursor::at_line_end() const {
  return at_end() || m_text[m_pos] == '\n' || m_text[m_pos] == '\r';
}

void TextCursor::skip_line() {
  while (!at_end() && m_text[m_pos] != '\n' && m_text[m_pos] != '\r') ++m_pos;
  consume_line_end();
}

std::string_view TextCursor::rest_of_line() {
  const std::size_t begin = m_pos;
  while (!at_end() && m_text[m_pos] != '\n' && m_text[m_pos] != '\r') ++m_pos;
  return m_text.substr(begin, m_pos - begin);
}

std::string_view TextCursor::peek_token() {
  skip_space();
  std::size_t end = m_pos;
  while (end < m_text.size() && !is_space(m_text[end])) ++end;
  return m_text.substr(m_pos, end - m_pos);
}

std::string_view TextCursor::next_token() {
  const std::string_view token = peek_token();
  m_pos += token.size();
  return token;
}

std::string_view TextCursor::next_token_on_line() {
  skip_inline_space();
  if (at_line_end()) return {};
  const std::size_t begin = m_pos;
  while (m_pos < m_text.size() && !is_space(m_text[m_pos])) ++m_pos;
  return m_text.substr(begin, m_pos - begin);
}

std::string_view TextCursor::next_token_on_line(char comment) {
  skip_inline_space();
  if (peek_char() == comment) return {};
  return next_token_on_line();
}

bool TextCursor::skip_to_content(char comment) {
  for (;;) {
    skip_space();
    if (at_end()) return false;
    if (m_text[m_pos] != comment) return true;
    skip_line();
  }
}

bool TextCursor::at_line_end_or_comment(char comment) {
  skip_inline_space();
  if (peek_char() == comment) rest_of_line();
  return at_line_end();
}

void TextCursor::expect_line_end(char comment, std::string_view what) {
  if (!at_line_end_or_comment(comment)) fail_expected(what);
}

std::string TextCursor::describe_next() {
  skip_inline_space();
  if (at_end()) return "end of file";
  if (at_line_end()) return "end of line";
  std::size_t end = m_pos;
  while (end < m_text.size() && !is_space(m_text[end])) ++end;
  return "'" + quote_token(m_text.substr(m_pos, end - m_pos)) + "'";
}

void TextCursor::fail_expected(std::string_view expected) {
  fail_expected_at(mark(), expected);
}

void TextCursor::fail_expected_at(const Mark& at, std::string_view expected,
                                  std::string_view suffix) {
  reset(at);
  const std::string found = describe_next();
  fail_at(m_line, column(),
          "expected " + std::string(expected) + ", found " + found + std::string(suffix));
}

void TextCursor::fail_at(std::size_t line, std::size_t column, const std::string& message) const {
  throw ParseError(m_path, line, column, message);
}

void TextCursor::expect(std::string_view keyword) {
  skip_space();
  if (peek_token() != keyword) fail_expected("'" + std::string(keyword) + "'");
  m_pos += keyword.size();
}

double TextCursor::next_number(std::string_view what, bool same_line) {
  if (same_line) {
    skip_inline_space();
    if (at_line_end()) fail_expected(what);
  } else {
    skip_space();
  }
  const char* first = m_text.data() + m_pos;
  double value = 0.0;
  switch (parse_number(first, m_text.data() + m_text.size(), value)) {
    case NumberStatus::Ok:
      break;
    case NumberStatus::NotANumber:
      fail_expected(what);
    case NumberStatus::NotFinite:
      fail_expected(std::string(what) + " (a finite number)");
  }
  m_pos = static_cast<std::size_t>(first - m_text.data());
  return value;
}

long long TextCursor::next_integer(std::string_view what, long long min, long long max,
                                   bool same_line) {
  if (same_line) {
    skip_inline_space();
    if (at_line_end()) fail_expected(what);
  } else {
    skip_space();
  }
  const char* begin = m_text.data() + m_pos;
  const char* end = m_text.data() + m_text.size();
  const char* start = begin;
  if (start != end && *start == '+' && !(end - start > 1 && start[1] == '-')) ++start;
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(start, end, value);
  if (ec != std::errc() || (ptr != end && !is_space(*ptr)) || value < min || value > max) {
    fail_expected(std::string(what));
  }
  m_pos = static_cast<std::size_t>(ptr - m_text.data());
  return value;
}

std::vector<CsvField> split_csv_fields(std::string_view row) {
  std::vector<CsvField> fields;
  std::size_t begin = 0;
  for (;;) {
    std::size_t end = row.find(',', begin);
    if (end == std::string_view::npos) end = row.size();
    std::size_t b = begin, e = end;
    while (b < e && is_blank(row[b])) ++b;
    while (e > b && is_blank(row[e - 1])) --e;
    fields.push_back({row.substr(b, e - b), b + 1});
    if (end == row.size()) break;
    begin = end + 1;
  }
  return fields;
}

bool next_csv_row(TextCursor& cur, CsvRow& row) {
  while (!cur.at_end()) {
    row.line = cur.line();
    row.text = cur.rest_of_line();
    cur.consume_line_end();
    std::size_t lead = 0;
    while (lead < row.text.size() && is_blank(row.text[lead])) ++lead;
    if (lead == row.text.size() || row.text[lead] == '#') continue;
    row.fields = split_csv_fields(row.text);
    return true;
  }
  return false;
}

namespace {
char lower_ascii_char(char c) {
  return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
}
}  // namespace

std::string ascii_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = lower_ascii_char(c);
  return out;
}

bool ascii_iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (lower_ascii_char(a[i]) != lower_ascii_char(b[i])) return false;
  }
  return true;
}

}  // namespace motionmap
