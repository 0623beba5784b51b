#include "motionmap/pipeline/labels.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <unordered_map>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/core/metric.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/points.h"

namespace motionmap::pipeline {

namespace {

// Names a label may not take: the map CSV's own columns and the colourings that are not labels.
constexpr std::string_view kReservedNames[] = {"clip", "frame", "x",     "y",
                                               "z",    "time",  "start", "end"};

// A token from a file or the command line in quotes, bytes that are not printable ASCII escaped.
std::string quoted(std::string_view token) {
  return "'" + quote_token(token) + "'";
}

bool reserved(std::string_view name) {
  return std::find(std::begin(kReservedNames), std::end(kReservedNames), name) !=
         std::end(kReservedNames);
}

// Whether `s` is well-formed UTF-8 (no overlong forms, no surrogates, ≤ U+10FFFF).
bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      extra = 1;
      cp = c & 0x1F;
    } else if (c >= 0xE0 && c <= 0xEF) {
      extra = 2;
      cp = c & 0x0F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      extra = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + std::size_t(extra) >= s.size()) return false;
    for (int e = 1; e <= extra; ++e) {
      const auto cc = static_cast<unsigned char>(s[i + std::size_t(e)]);
      if ((cc & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (cc & 0x3F);
    }
    if ((extra == 2 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
        (extra == 3 && (cp < 0x10000 || cp > 0x10FFFF))) {
      return false;
    }
    i += std::size_t(extra) + 1;
  }
  return true;
}

// Why `text` cannot be a label name or value (empty when it can).
std::string label_text_problem(std::string_view text, bool is_name) {
  if (is_name && text.empty()) return "an empty label name";
  if (text.size() > std::size_t(kMaxLabelBytes)) {
    return std::string(is_name ? "a label name" : "a label value") + " of " +
           std::to_string(text.size()) + " bytes (at most " + std::to_string(kMaxLabelBytes) + ")";
  }
  if (!valid_utf8(text)) {
    return std::string(is_name ? "a label name" : "a label value") + " that is not valid UTF-8";
  }
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    // C0 controls, DEL, and the C1 controls U+0080-U+009F (0xC2 0x80-0x9F in UTF-8).
    const bool c1 =
        c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) < 0xA0;
    if (c < 0x20 || c == 0x7F || c1) {
      return std::string(is_name ? "a label name" : "a label value") +
             " holding a control character";
    }
  }
  if (is_name && reserved(text)) {
    return "the label name '" + std::string(text) +
           "', which is reserved (clip, frame, x, y, z, time, start and end are not labels)";
  }
  return {};
}

// A file's name without its folder and its extension.
std::string stem(std::string_view path) {
  std::string name = base_name(path);
  const std::size_t dot = name.rfind('.');
  if (dot != std::string::npos && dot > 0) name.resize(dot);
  return name;
}

bool valid_field_name(std::string_view name) {
  if (name.empty()) return false;
  if (!(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

// ECMAScript escaping of one literal character.
std::string regex_literal(char c) {
  static const std::string_view special = "\\^$.|?*+()[]{}/";
  if (special.find(c) != std::string_view::npos) return std::string("\\") + c;
  return std::string(1, c);
}

// The clips' names the label files may use: the path as given, the file name, the stem. A name
// two clips share maps to −2 (ambiguous).
class ClipNames {
 public:
  explicit ClipNames(std::span<const std::string> paths) : m_paths(paths) {
    for (std::size_t i = 0; i < paths.size(); ++i) {
      add(m_by_path, paths[i], int(i));
      add(m_by_file, base_name(paths[i]), int(i));
      add(m_by_stem, stem(paths[i]), int(i));
    }
  }
  // The clip `name` names; −1 unknown, −2 ambiguous.
  int find(const std::string& name) const {
    for (const auto* table : {&m_by_path, &m_by_file, &m_by_stem}) {
      auto it = table->find(name);
      if (it != table->end()) return it->second;
    }
    return -1;
  }
  std::string examples() const {
    std::string s;
    for (std::size_t i = 0; i < m_paths.size() && i < 3; ++i) {
      s += (i ? ", " : "") + quoted(stem(m_paths[i]));
    }
    if (m_paths.size() > 3) s += ", …";
    return s;
  }
  std::size_t size() const { return m_paths.size(); }

 private:
  static void add(std::unordered_map<std::string, int>& table, const std::string& key, int i) {
    auto [it, inserted] = table.emplace(key, i);
    if (!inserted && it->second != i) it->second = -2;
  }
  std::span<const std::string> m_paths;
  std::unordered_map<std::string, int> m_by_path, m_by_file, m_by_stem;
};

// What both file formats build: the label names, then rows of (clip name, start, end, values).
class TableBuilder {
 public:
  TableBuilder(std::span<const std::string> paths, std::span<const int> frame_counts,
               std::string path)
      : m_names(paths),
        m_paths(paths.begin(), paths.end()),
        m_frames(frame_counts),
        m_path(std::move(path)) {
    if (!m_frames.empty() && m_frames.size() != paths.size()) {
      throw ParameterError("labels: " + std::to_string(frame_counts.size()) + " frame counts for " +
                           std::to_string(paths.size()) + " clips");
    }
  }

  [[noreturn]] void fail(std::size_t line, std::size_t column, const std::string& message) const {
    throw ParseError(m_path, line, column, message);
  }

  // Adds a label column; returns its index.
  int label(std::string_view name, std::size_t line, std::size_t column) {
    const std::string problem = label_text_problem(name, true);
    if (!problem.empty()) fail(line, column, "expected a label name, found " + problem);
    const auto it = std::find(table.names.begin(), table.names.end(), name);
    if (it != table.names.end()) return int(it - table.names.begin());
    if (int(table.names.size()) == kMaxLabels) {
      fail(line, column,
           "more than " + std::to_string(kMaxLabels) + " labels (at " + quoted(name) + ")");
    }
    table.names.emplace_back(name);
    return int(table.names.size()) - 1;
  }

  int clip(const std::string& name, std::size_t line, std::size_t column) const {
    const int c = m_names.find(name);
    if (c == -1) {
      fail(line, column,
           "unknown clip " + quoted(name) + ": not one of the " + std::to_string(m_names.size()) +
               " clips mapped (" + m_names.examples() +
               "; a clip is named by its path, file name or file name without extension)");
    }
    if (c == -2) {
      fail(line, column,
           "clip " + quoted(name) +
               " is ambiguous: several clips mapped have that name; give the path");
    }
    return c;
  }

  int frame(std::string_view text, std::size_t line, std::size_t column, const char* what) const {
    int value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < 0) {
      fail(line, column,
           std::string("expected the ") + what + " frame (an integer ≥ 0), found " + quoted(text));
    }
    return value;
  }

  void check_range(int clip, int first, int last, std::size_t line, std::size_t column) const {
    if (first > last) {
      fail(line, column,
           "start " + std::to_string(first) + " is after end " + std::to_string(last) +
               " (frames are inclusive: start ≤ end)");
    }
    if (!m_frames.empty() && last >= m_frames[std::size_t(clip)]) {
      fail(line, column,
           "frame " + std::to_string(last) + " is beyond clip " +
               quoted(base_name(m_paths[std::size_t(clip)])) + ", whose frames are 0-" +
               std::to_string(m_frames[std::size_t(clip)] - 1));
    }
  }

  void value(int clip, int first, int last, int label, std::string_view value, std::size_t line,
             std::size_t column) {
    const std::string problem = label_text_problem(value, false);
    if (!problem.empty()) fail(line, column, "expected a label value, found " + problem);
    table.spans.push_back({clip, first, last, label, std::string(value)});
    m_labelled.insert(clip);
  }

  LabelTable finish(std::size_t line) {
    if (table.names.empty()) fail(line, 1, "expected at least one label column besides the clip");
    if (table.spans.empty()) fail(line, 1, "no labels: the file has no rows after its header");
    if (m_labelled.size() < m_names.size()) {
      table.notes.push_back(m_path + ": " + std::to_string(m_names.size() - m_labelled.size()) +
                            " of " + std::to_string(m_names.size()) +
                            " clips have no labels there (their label is \"\" unless their "
                            "file names give one)");
    }
    return std::move(table);
  }

  LabelTable table;

 private:
  ClipNames m_names;
  std::vector<std::string> m_paths;
  std::span<const int> m_frames;
  std::string m_path;
  std::set<int> m_labelled;
};

// The text's lines (LF, CRLF or CR ends), each with its number.
std::vector<std::pair<std::size_t, std::string_view>> split_lines(std::string_view text) {
  std::vector<std::pair<std::size_t, std::string_view>> lines;
  std::size_t start = 0, number = 1;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i == text.size() || text[i] == '\n' || text[i] == '\r') {
      lines.emplace_back(number++, text.substr(start, i - start));
      if (i < text.size() && text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      start = i + 1;
    }
  }
  return lines;
}

// A small JSON reader for label files: objects, arrays, strings, integers (what labels hold).
class JsonReader {
 public:
  JsonReader(std::string_view text, std::string path) : m_text(text), m_path(std::move(path)) {}

  struct Member;  // a key and its value (not a std::pair: Value is incomplete inside itself)
  struct Value {
    enum Kind { String, Number, Object_, Array, Other } kind = Other;
    std::string text;  // String: the string; Number: the number's text
    std::vector<Member> members;
    std::vector<Value> items;
    std::size_t line = 1, column = 1;
  };
  struct Member {
    std::string first;
    Value second;
  };

  Value document() {
    Value v = value(0);
    skip_space();
    if (m_pos < m_text.size()) fail("expected the end of the file after the JSON value");
    return v;
  }

  [[noreturn]] void fail_at(std::size_t line, std::size_t column, const std::string& message) {
    throw ParseError(m_path, line, column, message);
  }

 private:
  [[noreturn]] void fail(const std::string& message) {
    const auto [line, column] = where(m_pos);
    const std::string found = m_pos < m_text.size() ? ", found " + quoted(m_text.substr(m_pos, 1))
                                                    : ", found the end of the file";
    throw ParseError(m_path, line, column, message + found);
  }
  std::pair<std::size_t, std::size_t> where(std::size_t pos) const {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < pos && i < m_text.size(); ++i) {
      if (m_text[i] == '\n' ||
          (m_text[i] == '\r' && (i + 1 >= m_text.size() || m_text[i + 1] != '\n'))) {
        ++line;
        column = 1;
      } else if (m_text[i] != '\r') {
        ++column;
      }
    }
    return {line, column};
  }
  void skip_space() {
    while (m_pos < m_text.size() && (m_text[m_pos] == ' ' || m_text[m_pos] == '\t' ||
                                     m_text[m_pos] == '\n' || m_text[m_pos] == '\r')) {
      ++m_pos;
    }
  }
  Value value(int depth) {
    if (depth > 64) fail("JSON nested too deeply");
    skip_space();
    Value v;
    std::tie(v.line, v.column) = where(m_pos);
    if (m_pos >= m_text.size()) fail("expected a JSON value");
    const char c = m_text[m_pos];
    if (c == '{') {
      v.kind = Value::Object_;
      ++m_pos;
      skip_space();
      if (m_pos < m_text.size() && m_text[m_pos] == '}') {
        ++m_pos;
        return v;
      }
      while (true) {
        skip_space();
        if (m_pos >= m_text.size() || m_text[m_pos] != '"') fail("expected a key in quotes");
        const auto [kl, kc] = where(m_pos);
        std::string key = string();
        for (const auto& member : v.members) {
          if (member.first == key) fail_at(kl, kc, "duplicate key " + quoted(key));
        }
        skip_space();
        if (m_pos >= m_text.size() || m_text[m_pos] != ':') fail("expected ':'");
        ++m_pos;
        v.members.push_back(Member{std::move(key), value(depth + 1)});
        skip_space();
        if (m_pos < m_text.size() && m_text[m_pos] == ',') {
          ++m_pos;
          continue;
        }
        if (m_pos < m_text.size() && m_text[m_pos] == '}') {
          ++m_pos;
          return v;
        }
        fail("expected ',' or '}'");
      }
    }
    if (c == '[') {
      v.kind = Value::Array;
      ++m_pos;
      skip_space();
      if (m_pos < m_text.size() && m_text[m_pos] == ']') {
        ++m_pos;
        return v;
      }
      while (true) {
        v.items.push_back(value(depth + 1));
        skip_space();
        if (m_pos < m_text.size() && m_text[m_pos] == ',') {
          ++m_pos;
          continue;
        }
        if (m_pos < m_text.size() && m_text[m_pos] == ']') {
          ++m_pos;
          return v;
        }
        fail("expected ',' or ']'");
      }
    }
    if (c == '"') {
      v.kind = Value::String;
      v.text = string();
      return v;
    }
    if (c == '-' || (c >= '0' && c <= '9')) {
      v.kind = Value::Number;
      const std::size_t start = m_pos;
      while (m_pos < m_text.size() &&
             std::string_view("+-0123456789.eE").find(m_text[m_pos]) != std::string_view::npos) {
        ++m_pos;
      }
      v.text = std::string(m_text.substr(start, m_pos - start));
      return v;
    }
    for (const std::string_view word : {"true", "false", "null"}) {
      if (m_text.substr(m_pos, word.size()) == word) {
        m_pos += word.size();
        v.text = std::string(word);
        return v;
      }
    }
    fail("expected a JSON value");
  }
  static void append_utf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
      out += char(cp);
    } else if (cp < 0x800) {
      out += char(0xC0 | (cp >> 6));
      out += char(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += char(0xE0 | (cp >> 12));
      out += char(0x80 | ((cp >> 6) & 0x3F));
      out += char(0x80 | (cp & 0x3F));
    } else {
      out += char(0xF0 | (cp >> 18));
      out += char(0x80 | ((cp >> 12) & 0x3F));
      out += char(0x80 | ((cp >> 6) & 0x3F));
      out += char(0x80 | (cp & 0x3F));
    }
  }
  std::uint32_t hex4() {
    if (m_pos + 4 > m_text.size()) fail("expected 4 hex digits after \\u");
    std::uint32_t v = 0;
    const auto [end, ec] = std::from_chars(m_text.data() + m_pos, m_text.data() + m_pos + 4, v, 16);
    if (ec != std::errc() || end != m_text.data() + m_pos + 4)
      fail("expected 4 hex digits after \\u");
    m_pos += 4;
    return v;
  }
  std::string string() {
    ++m_pos;  // the opening quote
    std::string out;
    while (true) {
      if (m_pos >= m_text.size()) fail("expected '\"' closing the string");
      const char c = m_text[m_pos++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) {
        --m_pos;
        fail("expected '\"' closing the string (a control character in a string)");
      }
      if (c != '\\') {
        out += c;
        continue;
      }
      if (m_pos >= m_text.size()) fail("expected an escape after '\\'");
      const char e = m_text[m_pos++];
      switch (e) {
        case '"':
          out += '"';
          break;
        case '\\':
          out += '\\';
          break;
        case '/':
          out += '/';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u': {
          std::uint32_t cp = hex4();
          if (cp >= 0xD800 && cp <= 0xDBFF && m_text.substr(m_pos, 2) == "\\u") {
            m_pos += 2;
            const std::uint32_t low = hex4();
            if (low < 0xDC00 || low > 0xDFFF) fail("expected a low surrogate");
            cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
          } else if (cp >= 0xD800 && cp <= 0xDFFF) {
            fail("expected a valid \\u escape (a lone surrogate)");
          }
          append_utf8(out, cp);
          break;
        }
        default:
          --m_pos;
          fail("expected a valid escape after '\\'");
      }
    }
  }

  std::string_view m_text;
  std::string m_path;
  std::size_t m_pos = 0;
};

// Adds one JSON object of labels for clip `clip_name` (the object form's value, or an array
// item without its "clip").
void add_json_labels(TableBuilder& builder, JsonReader& reader, const JsonReader::Value& object,
                     const std::string& clip_name, std::size_t clip_line, std::size_t clip_column,
                     bool spans_allowed) {
  const int clip = builder.clip(clip_name, clip_line, clip_column);
  int first = 0, last = LabelSpan::kToEnd;
  const JsonReader::Value* start = nullptr;
  const JsonReader::Value* end = nullptr;
  for (const auto& [key, value] : object.members) {
    if (spans_allowed && key == "start") start = &value;
    if (spans_allowed && key == "end") end = &value;
  }
  if ((start == nullptr) != (end == nullptr)) {
    const JsonReader::Value& given = start ? *start : *end;
    reader.fail_at(given.line, given.column, "expected both \"start\" and \"end\", or neither");
  }
  if (start) {
    for (const JsonReader::Value* v : {start, end}) {
      if (v->kind != JsonReader::Value::Number) {
        reader.fail_at(v->line, v->column, "expected a frame (an integer ≥ 0)");
      }
    }
    first = builder.frame(start->text, start->line, start->column, "start");
    last = builder.frame(end->text, end->line, end->column, "end");
    builder.check_range(clip, first, last, start->line, start->column);
  }
  bool any = false;
  for (const auto& [key, value] : object.members) {
    if (key == "clip" || (spans_allowed && (key == "start" || key == "end"))) continue;
    if (value.kind != JsonReader::Value::String) {
      reader.fail_at(value.line, value.column,
                     "expected the label " + quoted(key) + " as a string");
    }
    const int label = builder.label(key, value.line, value.column);
    builder.value(clip, first, last, label, value.text, value.line, value.column);
    any = true;
  }
  if (!any) reader.fail_at(object.line, object.column, "expected at least one label");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// File names

NamePattern::NamePattern(std::string pattern) : m_pattern(std::move(pattern)) {
  const std::string where = "label pattern " + quoted(m_pattern);
  auto add_name = [&](std::string name) {
    if (!valid_field_name(name)) {
      throw ParameterError(where + ": " + quoted(name) +
                           " is not a label name (letters, digits and '_', not starting with a "
                           "digit)");
    }
    const std::string problem = label_text_problem(name, true);
    if (!problem.empty()) throw ParameterError(where + ": " + problem);
    if (std::find(m_names.begin(), m_names.end(), name) != m_names.end()) {
      throw ParameterError(where + ": the label " + quoted(name) + " is given twice");
    }
    m_names.push_back(std::move(name));
  };
  int group = 0;
  if (m_pattern.rfind("re:", 0) == 0) {
    // A regular expression: named groups become plain groups, numbered as ECMAScript numbers
    // them (every '(' that is not "(?", outside brackets and escapes).
    const std::string source = m_pattern.substr(3);
    bool in_class = false;
    for (std::size_t i = 0; i < source.size(); ++i) {
      const char c = source[i];
      if (c == '\\') {
        m_regex += c;
        if (i + 1 < source.size()) m_regex += source[++i];
        continue;
      }
      if (in_class) {
        if (c == ']') in_class = false;
        m_regex += c;
        continue;
      }
      if (c == '[') {
        in_class = true;
        m_regex += c;
        if (i + 1 < source.size() && source[i + 1] == ']') m_regex += source[++i];
        continue;
      }
      if (c != '(') {
        m_regex += c;
        continue;
      }
      const std::string_view rest = std::string_view(source).substr(i + 1);
      std::size_t name_start = 0;
      if (rest.rfind("?P<", 0) == 0) {
        name_start = 3;
      } else if (rest.rfind("?<", 0) == 0 && rest.size() > 2 && rest[2] != '=' && rest[2] != '!') {
        name_start = 2;
      }
      if (name_start > 0) {
        const std::size_t close = rest.find('>', name_start);
        if (close == std::string_view::npos) {
          throw ParameterError(where + ": expected '>' closing a group name");
        }
        add_name(std::string(rest.substr(name_start, close - name_start)));
        m_groups.push_back(++group);
        m_regex += '(';
        i += close + 1;
        continue;
      }
      if (!rest.empty() && rest[0] == '?') {
        m_regex += c;  // (?: (?= (?!: not a capture
        continue;
      }
      ++group;
      m_regex += c;
    }
    if (m_names.empty()) {
      throw ParameterError(where +
                           ": the regular expression has no named group such as (?P<action>…)");
    }
  } else {
    // A template: literal text and {name} fields, matched at the end of the stem.
    std::string_view text = m_pattern;
    bool anchored = false;
    if (!text.empty() && text[0] == '^') {
      anchored = true;
      text.remove_prefix(1);
    }
    struct Piece {
      bool field;
      std::string text;  // the literal, or the field's name ("" or "_": discarded)
    };
    std::vector<Piece> pieces;
    for (std::size_t i = 0; i < text.size(); ++i) {
      const char c = text[i];
      if ((c == '{' || c == '}') && i + 1 < text.size() && text[i + 1] == c) {
        if (pieces.empty() || pieces.back().field) pieces.push_back({false, {}});
        pieces.back().text += c;
        ++i;
        continue;
      }
      if (c == '}') throw ParameterError(where + ": '}' without '{' (write '}}' for a brace)");
      if (c == '{') {
        const std::size_t close = text.find('}', i);
        if (close == std::string_view::npos) {
          throw ParameterError(where + ": '{' without '}' (write '{{' for a brace)");
        }
        if (!pieces.empty() && pieces.back().field) {
          throw ParameterError(where +
                               ": two fields with no text between them cannot be told apart");
        }
        pieces.push_back({true, std::string(text.substr(i + 1, close - i - 1))});
        i = close;
        continue;
      }
      if (pieces.empty() || pieces.back().field) pieces.push_back({false, {}});
      pieces.back().text += c;
    }
    // A field holds no occurrence of the first character of the text after it (the separator),
    // or, last, of the last character of the text before it; alone, anything.
    const auto field_class = [&](std::size_t p) {
      char stop = '\0';
      if (p + 1 < pieces.size()) {
        stop = pieces[p + 1].text.front();
      } else if (p > 0) {
        stop = pieces[p - 1].text.back();
      }
      if (stop == '\0') return std::string(".");
      const bool escape = stop == '\\' || stop == ']' || stop == '^' || stop == '-' || stop == '[';
      return std::string("[^") + (escape ? "\\" : "") + stop + "]";
    };
    m_regex = anchored ? "^" : "";
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      const Piece& piece = pieces[p];
      if (!piece.field) {
        for (const char c : piece.text) m_regex += regex_literal(c);
        continue;
      }
      m_regex += "(" + field_class(p) + "+)";
      ++group;
      if (piece.text.empty() || piece.text == "_") continue;
      add_name(piece.text);
      m_groups.push_back(group);
    }
    m_regex += "$";
    if (m_names.empty()) {
      throw ParameterError(where + ": no {name} field (e.g. '{action}_{style}_{take}')");
    }
  }
  try {
    std::regex compiled(m_regex, std::regex::ECMAScript);
    if (int(compiled.mark_count()) < group) {
      throw ParameterError(where + ": the groups could not be numbered");
    }
  } catch (const std::regex_error& e) {
    throw ParameterError(where + ": not a valid regular expression (" + e.what() + ")");
  }
}

std::optional<std::vector<std::string>> NamePattern::match(std::string_view path) const {
  const std::regex compiled(m_regex, std::regex::ECMAScript);
  const std::string name = stem(path);
  std::smatch m;
  if (!std::regex_search(name, m, compiled)) return std::nullopt;
  std::vector<std::string> values;
  values.reserve(m_groups.size());
  for (const int g : m_groups)
    values.push_back(m[std::size_t(g)].matched ? m[std::size_t(g)].str() : "");
  return values;
}

LabelTable labels_from_names(std::span<const std::string> paths, const NamePattern& pattern) {
  LabelTable table;
  table.names = pattern.names();
  for (std::size_t c = 0; c < paths.size(); ++c) {
    const std::optional<std::vector<std::string>> values = pattern.match(paths[c]);
    if (!values) {
      throw ParameterError(paths[c] + ": error: the file name " + quoted(stem(paths[c])) +
                           " does not match the label pattern " + quoted(pattern.pattern()));
    }
    for (std::size_t l = 0; l < values->size(); ++l) {
      const std::string problem = label_text_problem((*values)[l], false);
      if (!problem.empty()) {
        throw ParameterError(paths[c] + ": error: the label " + quoted(table.names[l]) + " is " +
                             problem);
      }
      table.spans.push_back({int(c), 0, LabelSpan::kToEnd, int(l), (*values)[l]});
    }
  }
  return table;
}

// ---------------------------------------------------------------------------------------------
// Label files

std::string csv_field(std::string_view text) {
  const bool quote = text.find_first_of(",\"\r\n") != std::string_view::npos ||
                     (!text.empty() && (text.front() == ' ' || text.front() == '\t' ||
                                        text.back() == ' ' || text.back() == '\t'));
  if (!quote) return std::string(text);
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::vector<std::pair<std::string, std::size_t>> split_quoted_csv(std::string_view line,
                                                                  std::size_t line_number,
                                                                  const std::string& path) {
  std::vector<std::pair<std::string, std::size_t>> fields;
  std::size_t i = 0;
  while (true) {
    std::string text;
    // Leading blanks are not part of a field.
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t column = i + 1;
    if (i < line.size() && line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < line.size()) {
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            text += '"';
            i += 2;
            continue;
          }
          ++i;
          closed = true;
          break;
        }
        text += line[i++];
      }
      if (!closed) {
        throw ParseError(path, line_number, column, "expected '\"' closing the quoted field");
      }
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i < line.size() && line[i] != ',') {
        throw ParseError(path, line_number, i + 1,
                         "expected ',' after the quoted field, found " + quoted(line.substr(i, 1)));
      }
    } else {
      const std::size_t end = line.find(',', i);
      std::string_view field = line.substr(i, end == std::string_view::npos ? line.npos : end - i);
      while (!field.empty() && (field.back() == ' ' || field.back() == '\t'))
        field.remove_suffix(1);
      text = std::string(field);
      i = end == std::string_view::npos ? line.size() : end;
    }
    fields.emplace_back(std::move(text), column);
    if (i >= line.size()) break;
    ++i;  // the comma
  }
  return fields;
}

LabelTable parse_label_csv(std::string_view text, std::span<const std::string> paths,
                           std::span<const int> frame_counts, const std::string& path) {
  TableBuilder builder(paths, frame_counts, path);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte order mark
  const auto lines = split_lines(text);
  std::size_t last_line = lines.empty() ? 1 : lines.back().first;
  bool header_seen = false;
  int clip_column = -1, start_column = -1, end_column = -1;
  std::vector<int> label_of;  // per column: its label, −1 for clip/start/end
  std::size_t columns = 0;
  for (const auto& [number, line] : lines) {
    std::string_view content = line;
    while (!content.empty() && (content.front() == ' ' || content.front() == '\t')) {
      content.remove_prefix(1);
    }
    if (content.empty() || content.front() == '#') continue;
    const auto fields = split_quoted_csv(line, number, path);
    if (!header_seen) {
      header_seen = true;
      columns = fields.size();
      std::set<std::string> seen;
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const std::string& name = fields[f].first;
        if (!seen.insert(name).second) {
          builder.fail(number, fields[f].second, "duplicate column " + quoted(name));
        }
        label_of.push_back(-1);
        if (name == "clip") {
          clip_column = int(f);
        } else if (name == "start") {
          start_column = int(f);
        } else if (name == "end") {
          end_column = int(f);
        } else {
          label_of.back() = builder.label(name, number, fields[f].second);
        }
      }
      if (clip_column < 0) {
        builder.fail(number, 1,
                     "expected a header with a 'clip' column (e.g. 'clip,action,style' or "
                     "'clip,start,end,action'), found " +
                         quoted(line));
      }
      if ((start_column < 0) != (end_column < 0)) {
        builder.fail(number, 1, "expected both 'start' and 'end' columns, or neither");
      }
      if (builder.table.names.empty()) {
        builder.fail(number, 1, "expected at least one label column besides clip, start and end");
      }
      continue;
    }
    if (fields.size() != columns) {
      builder.fail(number, fields.size() > columns ? fields[columns].second : line.size() + 1,
                   "expected " + std::to_string(columns) + " fields as the header has, found " +
                       std::to_string(fields.size()));
    }
    const auto& clip_field = fields[std::size_t(clip_column)];
    const int clip = builder.clip(clip_field.first, number, clip_field.second);
    int first = 0, last = LabelSpan::kToEnd;
    if (start_column >= 0) {
      const auto& s = fields[std::size_t(start_column)];
      const auto& e = fields[std::size_t(end_column)];
      first = builder.frame(s.first, number, s.second, "start");
      last = builder.frame(e.first, number, e.second, "end");
      builder.check_range(clip, first, last, number, s.second);
    }
    for (std::size_t f = 0; f < fields.size(); ++f) {
      if (label_of[f] < 0) continue;
      builder.value(clip, first, last, label_of[f], fields[f].first, number, fields[f].second);
    }
  }
  if (!header_seen) {
    builder.fail(last_line, 1,
                 "the file is empty: expected a header such as 'clip,action,style' and rows");
  }
  return builder.finish(last_line);
}

LabelTable parse_label_json(std::string_view text, std::span<const std::string> paths,
                            std::span<const int> frame_counts, const std::string& path) {
  TableBuilder builder(paths, frame_counts, path);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  JsonReader reader(text, path);
  const JsonReader::Value document = reader.document();
  using Value = JsonReader::Value;
  if (document.kind == Value::Array) {
    for (const Value& item : document.items) {
      if (item.kind != Value::Object_) {
        reader.fail_at(item.line, item.column,
                       "expected an object such as {\"clip\": \"a.bvh\", \"action\": \"walk\"}");
      }
      const Value* clip = nullptr;
      for (const auto& [key, value] : item.members) {
        if (key == "clip") clip = &value;
      }
      if (!clip || clip->kind != Value::String) {
        const Value& at = clip ? *clip : item;
        reader.fail_at(at.line, at.column, "expected \"clip\": the clip's name as a string");
      }
      add_json_labels(builder, reader, item, clip->text, clip->line, clip->column, true);
    }
  } else if (document.kind == Value::Object_) {
    for (const auto& [key, value] : document.members) {
      if (value.kind != Value::Object_) {
        reader.fail_at(value.line, value.column,
                       "expected the labels of clip " + quoted(key) +
                           " as an object such as {\"action\": \"walk\"}");
      }
      add_json_labels(builder, reader, value, key, value.line, value.column, false);
    }
  } else {
    reader.fail_at(document.line, document.column,
                   "expected an array of objects [{\"clip\": …, \"action\": …}] or an object "
                   "{\"clip name\": {\"action\": …}}");
  }
  return builder.finish(document.line);
}

LabelTable read_label_file(const std::string& path, std::span<const std::string> paths,
                           std::span<const int> frame_counts) {
  const std::string text = read_text_file(path);
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (first != std::string::npos && (text[first] == '[' || text[first] == '{')) {
    return parse_label_json(text, paths, frame_counts, path);
  }
  return parse_label_csv(text, paths, frame_counts, path);
}

// ---------------------------------------------------------------------------------------------
// Labels per sample

std::vector<int> LabelColumn::counts() const {
  std::vector<int> n(categories.size(), 0);
  for (const std::int32_t c : codes) ++n[std::size_t(c)];
  return n;
}

const LabelColumn* Labels::find(std::string_view name) const {
  for (const LabelColumn& c : columns) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

Labels sample_labels(const LabelTable& table, std::span<const int> clip_of,
                     std::span<const int> frame_of) {
  if (clip_of.size() != frame_of.size()) {
    throw ParameterError("labels: " + std::to_string(clip_of.size()) + " clips and " +
                         std::to_string(frame_of.size()) + " frames per sample");
  }
  Labels labels;
  for (std::size_t l = 0; l < table.names.size(); ++l) {
    // Spans of this label by clip, in the table's order (later ones win).
    std::map<int, std::vector<const LabelSpan*>> by_clip;
    for (const LabelSpan& span : table.spans) {
      if (span.label == int(l)) by_clip[span.clip].push_back(&span);
    }
    std::vector<const std::string*> value(clip_of.size());
    static const std::string kNone;
    std::set<std::string> distinct;
    for (std::size_t i = 0; i < clip_of.size(); ++i) {
      value[i] = &kNone;
      const auto it = by_clip.find(clip_of[i]);
      if (it != by_clip.end()) {
        for (auto s = it->second.rbegin(); s != it->second.rend(); ++s) {
          const LabelSpan& span = **s;
          if (frame_of[i] >= span.first && (span.last < 0 || frame_of[i] <= span.last)) {
            value[i] = &span.value;
            break;
          }
        }
      }
      distinct.insert(*value[i]);
    }
    LabelColumn column;
    column.name = table.names[l];
    column.categories.assign(distinct.begin(), distinct.end());
    column.codes.resize(clip_of.size());
    for (std::size_t i = 0; i < clip_of.size(); ++i) {
      column.codes[i] = std::int32_t(
          std::lower_bound(column.categories.begin(), column.categories.end(), *value[i]) -
          column.categories.begin());
    }
    labels.columns.push_back(std::move(column));
  }
  return labels;
}

void merge_labels(LabelTable& table, LabelTable later, const std::string& source) {
  // Each of later's labels: its index in the table's names, new names after the table's.
  std::vector<std::string> names = table.names;
  std::vector<int> index;
  for (const std::string& name : later.names) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) {
      index.push_back(int(it - names.begin()));
      continue;
    }
    if (int(names.size()) == kMaxLabels) {
      throw ParameterError(source + ": error: more than " + std::to_string(kMaxLabels) +
                           " labels together with the map's");
    }
    names.push_back(name);
    index.push_back(int(names.size()) - 1);
  }
  table.names = std::move(names);
  // Later spans win where they cover a frame (sample_labels: the last covering span).
  for (LabelSpan& span : later.spans) {
    span.label = index[std::size_t(span.label)];
    table.spans.push_back(std::move(span));
  }
  table.notes.insert(table.notes.end(), std::make_move_iterator(later.notes.begin()),
                     std::make_move_iterator(later.notes.end()));
}

LabelTable label_table(const Labels& labels, std::span<const int> clip_of,
                       std::span<const int> frame_of) {
  if (clip_of.size() != frame_of.size()) {
    throw ParameterError("labels: " + std::to_string(clip_of.size()) + " clips and " +
                         std::to_string(frame_of.size()) + " frames per sample");
  }
  // The samples by clip and frame: a run of equal values in this order covers no other sample.
  std::vector<std::size_t> order(clip_of.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return clip_of[a] != clip_of[b] ? clip_of[a] < clip_of[b] : frame_of[a] < frame_of[b];
  });
  LabelTable table;
  for (std::size_t l = 0; l < labels.columns.size(); ++l) {
    const LabelColumn& column = labels.columns[l];
    if (column.codes.size() != clip_of.size()) {
      throw ParameterError("labels: label " + quoted(column.name) + ": " +
                           std::to_string(column.codes.size()) + " values for " +
                           std::to_string(clip_of.size()) + " samples");
    }
    table.names.push_back(column.name);
    for (std::size_t r = 0; r < order.size();) {
      const std::size_t first = order[r];
      const int clip = clip_of[first];
      const std::int32_t code = column.codes[first];
      std::size_t end = r + 1;
      while (end < order.size() && clip_of[order[end]] == clip &&
             column.codes[order[end]] == code) {
        ++end;
      }
      const std::string& value = column.categories.at(std::size_t(code));
      if (!value.empty()) {
        table.spans.push_back({clip, frame_of[first], frame_of[order[end - 1]], int(l), value});
      }
      r = end;
    }
  }
  return table;
}

void check_labels(const Labels& labels, int samples) {
  if (int(labels.columns.size()) > kMaxLabels) {
    throw ParameterError("labels: " + std::to_string(labels.columns.size()) + " labels; at most " +
                         std::to_string(kMaxLabels));
  }
  std::set<std::string> names;
  for (const LabelColumn& column : labels.columns) {
    const std::string problem = label_text_problem(column.name, true);
    if (!problem.empty()) throw ParameterError("labels: " + problem);
    if (!names.insert(column.name).second) {
      throw ParameterError("labels: the label " + quoted(column.name) + " is given twice");
    }
    const std::string where = "labels: label " + quoted(column.name) + ": ";
    if (int(column.codes.size()) != samples) {
      throw ParameterError(where + std::to_string(column.codes.size()) + " values for " +
                           std::to_string(samples) + " samples");
    }
    if (column.categories.empty() && samples > 0) {
      throw ParameterError(where + "no values");
    }
    for (const std::string& value : column.categories) {
      const std::string value_problem = label_text_problem(value, false);
      if (!value_problem.empty()) throw ParameterError(where + value_problem);
    }
    for (std::size_t i = 0; i < column.codes.size(); ++i) {
      if (column.codes[i] < 0 || std::size_t(column.codes[i]) >= column.categories.size()) {
        throw ParameterError(where + "sample " + std::to_string(i) + " has value index " +
                             std::to_string(column.codes[i]) + "; expected 0-" +
                             std::to_string(int(column.categories.size()) - 1));
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Label accuracy

namespace {

// The voters of label_accuracy() without every frame's distance: the frames in order of a key
// (their first projection onto orthonormal directions), walked outwards from the query's, each
// tested against lower bounds of its distance before the distance is computed — the gap of the
// keys (which also ends the walk) and, with `bounded`, the distance of the projections (a
// projection onto orthonormal directions is no longer than the vector). A frame is skipped only
// when its bound less `margin` (for rounding) exceeds the k-th nearest distance kept of every
// label it could vote in: the voters kept are then those of a scan of every frame (the k
// smallest (distance, index) pairs, embed::NearestVoters), and so are the votes.
class ProjectedSearch {
 public:
  ProjectedSearch(const RowMatrix& projections, double margin, bool bounded)
      : m_margin(margin), m_bounded(bounded) {
    const int n = int(projections.rows());
    m_order.resize(std::size_t(n));
    for (int i = 0; i < n; ++i) m_order[std::size_t(i)] = i;
    std::stable_sort(m_order.begin(), m_order.end(),
                     [&](int a, int b) { return projections(a, 0) < projections(b, 0); });
    m_position.resize(std::size_t(n));
    m_sorted.resize(n, projections.cols());
    for (int p = 0; p < n; ++p) {
      m_position[std::size_t(m_order[std::size_t(p)])] = p;
      m_sorted.row(p) = projections.row(m_order[std::size_t(p)]);
    }
  }

  // Offers `query`'s candidates to voters[l] (frames of other clips than groups[query] with
  // codes[l][j] ≥ 0 and a finite distance(j)), skipping those that cannot be kept.
  template <class Distance>
  void search(int query, const Distance& distance, std::span<const std::span<const int>> codes,
              std::span<const int> groups, std::vector<embed::NearestVoters>& voters) const {
    const int n = int(m_order.size());
    const int p0 = m_position[std::size_t(query)];
    const int group = groups[std::size_t(query)];
    const double key = m_sorted(p0, 0);
    double bound = std::numeric_limits<double>::infinity();
    for (int lo = p0 - 1, hi = p0 + 1;;) {
      const double gap_lo = lo >= 0 ? key - m_sorted(lo, 0) : kInf;
      const double gap_hi = hi < n ? m_sorted(hi, 0) - key : kInf;
      const bool low = gap_lo <= gap_hi;
      if (low ? lo < 0 : hi >= n) break;
      const int p = low ? lo-- : hi++;
      // Every frame further along the keys is at least as far: none can be kept.
      if ((low ? gap_lo : gap_hi) - m_margin > bound) break;
      const int j = m_order[std::size_t(p)];
      if (groups[std::size_t(j)] == group) continue;
      bool candidate = false;
      for (const std::span<const int>& c : codes) candidate |= c[std::size_t(j)] >= 0;
      if (!candidate) continue;
      if (m_bounded && bound < kInf &&
          (m_sorted.row(p) - m_sorted.row(p0)).norm() - m_margin > bound)
        continue;
      const double d = distance(j);
      if (!std::isfinite(d)) continue;
      bound = 0.0;
      for (std::size_t l = 0; l < codes.size(); ++l) {
        if (codes[l][std::size_t(j)] >= 0) voters[l].offer(d, j);
        bound = std::max(bound, voters[l].bound());
      }
    }
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  RowMatrix m_sorted;           // the projections in key order
  std::vector<int> m_order;     // key position → frame
  std::vector<int> m_position;  // frame → key position
  double m_margin;
  bool m_bounded;
};

// The margin for rounding of bounds on distances between rows of magnitude up to `scale`: the
// rounding of a projection or a distance is ~1e-15 of it, far below this.
double rounding_margin(double scale) {
  return 1e-9 * (1.0 + scale);
}

// A search of the map's coordinates (keyed by the first; the distances are computed, being
// as cheap as a bound); nullopt when a coordinate is not finite.
std::optional<ProjectedSearch> map_search(const Eigen::MatrixXd& coordinates) {
  if (coordinates.cols() < 1 || !coordinates.allFinite()) return std::nullopt;
  const RowMatrix rows = coordinates;
  return ProjectedSearch(rows, rounding_margin(rows.rowwise().norm().maxCoeff()), false);
}

// A search of points by the Euclidean distance, on their projections onto their (up to) 8
// principal directions (embed::principal_axes of ≤ 20 000 rows: the directions need only be
// orthonormal, how well they fit changes the speed, not the result); nullopt when a value is
// not finite.
std::optional<ProjectedSearch> point_search(const RowMatrix& points) {
  const Eigen::Index dims = points.cols();
  if (points.rows() < 1 || dims < 1 || !points.allFinite()) return std::nullopt;
  const Eigen::Index m = std::min<Eigen::Index>(8, dims);
  // The largest first (the key spreads the frames most).
  const RowMatrix projections = points * embed::principal_axes(points, 20000).leftCols(m);
  return ProjectedSearch(projections, rounding_margin(points.rowwise().norm().maxCoeff()),
                         m < dims);
}

}  // namespace

std::vector<LabelAccuracy> label_accuracy(const features::FeatureSet& features,
                                          const Eigen::MatrixXd& coordinates, const Labels& labels,
                                          int k, int sample, const Control& control,
                                          bool feature_space) {
  const int n = features.num_samples();
  if (k < 1) throw ParameterError("label accuracy: k is " + std::to_string(k) + "; it must be ≥ 1");
  if (coordinates.rows() != n) {
    throw ParameterError("label accuracy: " + std::to_string(coordinates.rows()) +
                         " map points for " + std::to_string(n) + " samples");
  }
  check_labels(labels, n);
  const bool dense = features.has_distances();
  if (!dense && features.distance_input.rows() != n) {
    throw ParameterError(
        "label accuracy: the feature set has neither the distance matrix D nor the points it is "
        "computed from");
  }
  const Metric metric = features.distance == features::DistanceKind::Geodesic
                            ? Metric::QuaternionAngles
                            : Metric::Euclidean;

  // The labels measured: ≥ 2 values besides "", in ≥ 2 clips. Codes with "" as −1.
  struct Measured {
    const LabelColumn* column;
    std::vector<int> codes;
  };
  std::vector<Measured> measured;
  std::vector<char> labelled(static_cast<std::size_t>(n), 0);
  for (const LabelColumn& column : labels.columns) {
    const auto none = std::find(column.categories.begin(), column.categories.end(), "");
    const int none_code =
        none == column.categories.end() ? -1 : int(none - column.categories.begin());
    const int values = int(column.categories.size()) - (none_code >= 0 ? 1 : 0);
    std::set<int> clips;
    std::vector<int> codes(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      codes[std::size_t(i)] =
          column.codes[std::size_t(i)] == none_code ? -1 : column.codes[std::size_t(i)];
      if (codes[std::size_t(i)] >= 0) clips.insert(features.clip_of[std::size_t(i)]);
    }
    if (values < 2 || clips.size() < 2) continue;
    for (int i = 0; i < n; ++i) labelled[std::size_t(i)] |= char(codes[std::size_t(i)] >= 0);
    measured.push_back({&column, std::move(codes)});
  }
  if (measured.empty()) return {};

  // The queries: labelled frames (in some measured label), all or a seeded sample.
  std::vector<int> queries;
  for (int i = 0; i < n; ++i) {
    if (labelled[std::size_t(i)]) queries.push_back(i);
  }
  if (sample > 0 && int(queries.size()) > sample) {
    std::mt19937_64 random(20261128);
    for (int i = 0; i < sample; ++i) {
      std::uniform_int_distribution<int> pick(i, int(queries.size()) - 1);
      std::swap(queries[std::size_t(i)], queries[std::size_t(pick(random))]);
    }
    queries.resize(std::size_t(sample));
    std::sort(queries.begin(), queries.end());
  }

  // Per query and label: 1 when the vote is right, in the map (0) and the features (1).
  const std::size_t L = measured.size();
  std::vector<signed char> right(queries.size() * L * 2, -1);
  const std::span<const int> groups(features.clip_of);
  const auto distance = [&](int space, int i, int j) {
    if (space == 0) return (coordinates.row(j) - coordinates.row(i)).norm();
    if (dense) return features.D(j, i);
    return pose_distance(features.distance_input.row(i), features.distance_input.row(j), metric);
  };
  // The voters found without every frame's distance where a bound of the distance is at hand
  // (the map; the points by the Euclidean distance), the same as a scan of every frame finds;
  // else (D, the quaternion metric, values that are not finite) every frame's distance.
  std::optional<ProjectedSearch> search[2] = {map_search(coordinates),
                                              feature_space && !dense && metric == Metric::Euclidean
                                                  ? point_search(features.distance_input)
                                                  : std::nullopt};
  parallel_for(
      int(queries.size()),
      [&](int q) {
        const int i = queries[std::size_t(q)];
        // The labels this frame has (those it is a query of).
        std::vector<std::size_t> voted;
        std::vector<std::span<const int>> codes;
        for (std::size_t l = 0; l < L; ++l) {
          if (measured[l].codes[std::size_t(i)] < 0) continue;
          voted.push_back(l);
          codes.emplace_back(measured[l].codes);
        }
        std::vector<double> d;
        for (int space = 0; space < (feature_space ? 2 : 1); ++space) {
          std::vector<int> votes(voted.size());
          if (search[space]) {
            std::vector<embed::NearestVoters> voters(voted.size(), embed::NearestVoters(k));
            search[space]->search(
                i, [&](int j) { return distance(space, i, j); }, codes, groups, voters);
            for (std::size_t v = 0; v < voted.size(); ++v) votes[v] = voters[v].vote(codes[v]);
          } else {
            d.resize(static_cast<std::size_t>(n));
            for (int j = 0; j < n; ++j) d[std::size_t(j)] = distance(space, i, j);
            for (std::size_t v = 0; v < voted.size(); ++v)
              votes[v] = embed::knn_label_vote(d, codes[v], groups, groups[std::size_t(i)], k);
          }
          for (std::size_t v = 0; v < voted.size(); ++v) {
            const int truth = measured[voted[v]].codes[std::size_t(i)];
            right[(std::size_t(q) * L + voted[v]) * 2 + std::size_t(space)] =
                votes[v] == truth ? 1 : 0;
          }
        }
      },
      control);

  std::vector<LabelAccuracy> out;
  for (std::size_t l = 0; l < L; ++l) {
    LabelAccuracy a;
    a.label = measured[l].column->name;
    a.k = k;
    int hits[2] = {0, 0};
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const signed char m = right[(q * L + l) * 2];
      if (m < 0) continue;
      ++a.queries;
      hits[0] += m;
      hits[1] += right[(q * L + l) * 2 + 1];
    }
    if (a.queries == 0) continue;
    a.map = double(hits[0]) / a.queries;
    a.features =
        feature_space ? double(hits[1]) / a.queries : std::numeric_limits<double>::quiet_NaN();
    out.push_back(a);
  }
  return out;
}

namespace {
std::string fixed4(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}
}  // namespace

std::string describe_label_accuracy(std::span<const LabelAccuracy> accuracy) {
  std::string s;
  for (const LabelAccuracy& a : accuracy) {
    if (!s.empty()) s += ' ';
    s += "label_accuracy[" + a.label + "]=" + fixed4(a.map) + "/" + fixed4(a.features);
  }
  return s;
}

}  // namespace motionmap::pipeline
