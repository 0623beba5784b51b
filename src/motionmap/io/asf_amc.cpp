#include "motionmap/io/asf_amc.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/text_cursor.h"

namespace motionmap::io {

namespace {

// ---------------------------------------------------------------------------------------------
// Shared lexical helpers (both formats are line-oriented, with `#` comments).

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto x = static_cast<unsigned char>(a[i]);
    const auto y = static_cast<unsigned char>(b[i]);
    if (std::tolower(x) != std::tolower(y)) return false;
  }
  return true;
}

char next_char(const TextCursor& c) {
  return c.at_end() ? '\0' : c.text()[c.position()];
}

// Skips whitespace, blank lines and `#` comment lines (or comment tails). False at end of text.
bool skip_to_content(TextCursor& c) {
  for (;;) {
    c.skip_space();
    if (c.at_end()) return false;
    if (next_char(c) != '#') return true;
    c.skip_line();
  }
}

// Where a token starts, for messages about a token that is only judged after it has been read.
using Where = TextCursor::Mark;

Where where_inline(TextCursor& c) {
  c.skip_inline_space();
  return c.mark();
}

Where where_any(TextCursor& c) {
  c.skip_space();
  return c.mark();
}

// `expected <expected>, found <the token at w><suffix>`, at w.
[[noreturn]] void fail_at_where(TextCursor& c, const Where& w, const std::string& expected,
                                const std::string& suffix = "") {
  c.reset(w);
  const std::string found = c.describe_next();
  c.fail_at(c.line(), c.column(), "expected " + expected + ", found " + found + suffix);
}

// Skips blanks and a `#` comment tail; true if the line has nothing else left.
bool at_line_end_or_comment(TextCursor& c) {
  c.skip_inline_space();
  if (next_char(c) == '#') c.rest_of_line();
  return c.at_line_end();
}

// After a keyword's values: only blanks or a `#` comment may follow on the line.
void expect_line_end(TextCursor& c, std::string_view what = "end of line") {
  if (!at_line_end_or_comment(c)) c.fail_expected(what);
}

// A number on the current line, the motion loop's fast path: the message (`what()`) is only
// built when the value is bad, by letting the cursor's next_number report it.
template <typename What>
double number_on_line(TextCursor& c, const What& what) {
  c.skip_inline_space();
  const char* first = c.text().data() + c.position();
  double value = 0.0;
  if (!c.at_line_end() &&
      parse_number(first, c.text().data() + c.text().size(), value) == NumberStatus::Ok) {
    TextCursor::Mark m = c.mark();
    m.pos = static_cast<std::size_t>(first - c.text().data());  // a number spans no line end
    c.reset(m);
    return value;
  }
  return c.next_number(what(), true);  // throws the full message
}

// Next token on the current line, stopping at a `#` comment.
std::string_view token_on_line(TextCursor& c) {
  c.skip_inline_space();
  if (next_char(c) == '#') return {};
  return c.next_token_on_line();
}

std::optional<Dof> parse_dof(std::string_view s) {
  static constexpr std::array<std::pair<std::string_view, Dof>, 7> kDofs = {{{"rx", Dof::RX},
                                                                             {"ry", Dof::RY},
                                                                             {"rz", Dof::RZ},
                                                                             {"tx", Dof::TX},
                                                                             {"ty", Dof::TY},
                                                                             {"tz", Dof::TZ},
                                                                             {"l", Dof::L}}};
  for (const auto& [name, dof] : kDofs) {
    if (iequals(s, name)) return dof;
  }
  return std::nullopt;
}

std::string_view dof_name(Dof d) {
  static constexpr std::array<std::string_view, 7> kNames = {"rx", "ry", "rz", "tx",
                                                             "ty", "tz", "l"};
  return kNames[static_cast<int>(d)];
}

bool is_rotation(Dof d) {
  return d == Dof::RX || d == Dof::RY || d == Dof::RZ;
}
bool is_translation(Dof d) {
  return d == Dof::TX || d == Dof::TY || d == Dof::TZ;
}
int dof_axis(Dof d) {
  return static_cast<int>(d) % 3;
}  // RX,TX → 0, RY,TY → 1, RZ,TZ → 2

// "XYZ" (any case, any permutation) → the three axes.
std::optional<std::array<Axis, 3>> parse_axis_order(std::string_view s) {
  if (s.size() != 3) return std::nullopt;
  std::array<Axis, 3> out{};
  bool seen[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    const int a = std::tolower(static_cast<unsigned char>(s[i])) - 'x';
    if (a < 0 || a > 2 || seen[a]) return std::nullopt;
    seen[a] = true;
    out[i] = static_cast<Axis>(a);
  }
  return out;
}

// Acclaim composes Euler triples "first listed, first applied" (column vectors): angles (a, b, c)
// about axes (i, j, k) give R = Rk(c)·Rj(b)·Ri(a). Measured against CMU's BVH conversion.
Eigen::Quaterniond acclaim_euler(const std::array<Axis, 3>& order, const Eigen::Vector3d& angles) {
  const std::array<Axis, 3> reversed{order[2], order[1], order[0]};
  const std::array<double, 3> values{angles[2], angles[1], angles[0]};
  return euler_to_quat(reversed, values);
}

// Angles of an `axis`/`orientation` triple are indexed by axis (x y z), whatever the order.
Eigen::Vector3d axis_angles_in_order(const std::array<Axis, 3>& order, const Eigen::Vector3d& xyz) {
  return {xyz[static_cast<int>(order[0])], xyz[static_cast<int>(order[1])],
          xyz[static_cast<int>(order[2])]};
}

// ---------------------------------------------------------------------------------------------
// ASF

constexpr std::string_view kSections =
    "a section (':version', ':name', ':units', ':documentation', ':root', ':bonedata', "
    "':hierarchy')";

class AsfParser {
 public:
  AsfParser(std::string_view text, const std::string& path) : m_c(text, path) {}

  AsfSkeleton parse() {
    bool any = false;
    while (skip_to_content(m_c)) {
      const std::string_view token = m_c.peek_token();
      if (token.front() != ':') m_c.fail_expected(kSections);
      const Where at = where_any(m_c);
      const int section = section_index(token);
      if (section < 0) m_c.fail_expected(kSections);
      if (m_seen[section]) fail_at_where(m_c, at, "each section once", " again");
      m_seen[section] = true;
      any = true;
      m_c.next_token();
      switch (section) {
        case kVersion:
          m_c.rest_of_line();
          break;
        case kName:
          parse_name();
          break;
        case kUnits:
          parse_units();
          break;
        case kDocumentation:
          skip_section_body();
          break;
        case kRoot:
          parse_root();
          break;
        case kBonedata:
          parse_bonedata();
          break;
        case kHierarchy:
          parse_hierarchy();
          break;
        case kSkin:
          m_asf.warnings.push_back(m_c.path() + ":" + std::to_string(at.line) +
                                   ": warning: ':skin' section ignored (skin files are not used)");
          skip_section_body();
          break;
        default:
          break;
      }
    }
    if (!any) m_c.fail_expected(kSections);
    for (const int required : {kRoot, kBonedata, kHierarchy}) {
      if (!m_seen[required]) {
        m_c.fail_expected("section '" + std::string(kSectionNames[required]) + "'");
      }
    }
    link_hierarchy();
    return std::move(m_asf);
  }

 private:
  enum Section { kVersion, kName, kUnits, kDocumentation, kRoot, kBonedata, kHierarchy, kSkin };
  static constexpr std::array<std::string_view, 8> kSectionNames = {
      ":version", ":name", ":units", ":documentation", ":root", ":bonedata", ":hierarchy", ":skin"};

  struct Edge {
    std::string_view parent, child;
    Where parent_at, child_at;
  };

  static int section_index(std::string_view token) {
    for (std::size_t i = 0; i < kSectionNames.size(); ++i) {
      if (iequals(token, kSectionNames[i])) return static_cast<int>(i);
    }
    return -1;
  }

  // True when the cursor is at the end or at the next `:section` line.
  bool at_section_end() { return !skip_to_content(m_c) || next_char(m_c) == ':'; }

  void skip_section_body() {
    m_c.rest_of_line();
    for (;;) {
      m_c.skip_space();
      if (m_c.at_end() || next_char(m_c) == ':') return;
      m_c.skip_line();
    }
  }

  void parse_name() {
    std::string_view rest = m_c.rest_of_line();
    while (!rest.empty() && is_blank(rest.front())) rest.remove_prefix(1);
    while (!rest.empty() && is_blank(rest.back())) rest.remove_suffix(1);
    m_asf.name = std::string(rest);
  }

  double positive_number(std::string_view what) {
    const Where at = where_inline(m_c);
    const double v = m_c.next_number(what, true);
    if (!(v > 0.0)) fail_at_where(m_c, at, "a positive " + std::string(what));
    return v;
  }

  void parse_units() {
    while (!at_section_end()) {
      const std::string_view key = m_c.peek_token();
      if (iequals(key, "mass")) {
        m_c.next_token();
        m_asf.mass_unit = positive_number("mass unit");
      } else if (iequals(key, "length")) {
        m_c.next_token();
        m_asf.length_unit = positive_number("length unit");
      } else if (iequals(key, "angle")) {
        m_c.next_token();
        const Where at = where_inline(m_c);
        const std::string_view unit = token_on_line(m_c);
        if (iequals(unit, "deg")) {
          m_asf.angles_in_degrees = true;
        } else if (iequals(unit, "rad")) {
          m_asf.angles_in_degrees = false;
        } else {
          fail_at_where(m_c, at, "an angle unit ('deg' or 'rad')");
        }
      } else {
        m_c.fail_expected("a unit ('mass', 'length' or 'angle') or a section");
      }
      expect_line_end(m_c);
    }
  }

  Eigen::Vector3d three_numbers(std::string_view what) {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = m_c.next_number(what, true);
    return v;
  }

  std::array<Axis, 3> axis_order() {
    const Where at = where_inline(m_c);
    const auto order = parse_axis_order(token_on_line(m_c));
    if (!order) fail_at_where(m_c, at, "an axis order (a permutation of XYZ)");
    return *order;
  }

  // Dof names up to the end of the line, each at most once, at least one.
  std::vector<Dof> dof_list(bool allow_length, std::string_view expected) {
    std::vector<Dof> dofs;
    for (;;) {
      const Where at = where_inline(m_c);
      const std::string_view token = token_on_line(m_c);
      if (token.empty() && !dofs.empty()) return dofs;
      const auto dof = parse_dof(token);
      if (!dof || (!allow_length && *dof == Dof::L)) fail_at_where(m_c, at, std::string(expected));
      if (std::find(dofs.begin(), dofs.end(), *dof) != dofs.end()) {
        fail_at_where(m_c, at, "each dof once", " again");
      }
      dofs.push_back(*dof);
    }
  }

  void parse_root() {
    bool seen[4] = {false, false, false, false};
    static constexpr std::array<std::string_view, 4> kKeys = {"order", "axis", "position",
                                                              "orientation"};
    while (!at_section_end()) {
      const Where at = where_any(m_c);
      const std::string_view key = m_c.peek_token();
      int k = 0;
      while (k < 4 && !iequals(key, kKeys[k])) ++k;
      if (k == 4) {
        m_c.fail_expected(
            "a root keyword ('order', 'axis', 'position', 'orientation') or a section");
      }
      if (seen[k]) fail_at_where(m_c, at, "each root keyword once", " again");
      seen[k] = true;
      m_c.next_token();
      switch (k) {
        case 0:
          m_asf.root_order = dof_list(false, "a root dof (TX, TY, TZ, RX, RY or RZ)");
          break;
        case 1:
          m_asf.root_axis_order = axis_order();
          break;
        case 2:
          m_asf.root_position = three_numbers("root position");
          break;
        case 3:
          m_asf.root_orientation = three_numbers("root orientation");
          break;
        default:
          break;
      }
      expect_line_end(m_c);
    }
    if (!seen[0]) m_c.fail_expected("'order' in the :root section");
  }

  void parse_bonedata() {
    while (!at_section_end()) {
      if (!iequals(m_c.peek_token(), "begin")) m_c.fail_expected("'begin' or a section");
      m_c.next_token();
      expect_line_end(m_c);
      parse_bone();
    }
  }

  // A `(min max)` pair of a `limits` list; the parentheses may stick to the numbers or stand
  // alone, pairs may span lines. Limits may be ±inf.
  std::pair<double, double> limit_pair(const std::string& what) {
    Where at = where_any(m_c);
    std::string_view token = m_c.next_token();
    if (token.empty() || token.front() != '(') fail_at_where(m_c, at, "'(' opening " + what);
    token.remove_prefix(1);
    if (token.empty()) {
      at = where_any(m_c);
      token = m_c.next_token();
    } else {
      ++at.pos;  // the number after the '('
    }
    const double low = limit_number(token, at, "the lower " + what);
    at = where_any(m_c);
    token = m_c.next_token();
    const bool closed = !token.empty() && token.back() == ')';
    if (closed) token.remove_suffix(1);
    const double high = limit_number(token, at, "the upper " + what);
    if (!closed) {
      at = where_any(m_c);
      if (m_c.next_token() != ")") fail_at_where(m_c, at, "')' closing " + what);
    }
    return {low, high};
  }

  double limit_number(std::string_view token, const Where& at, const std::string& what) {
    const char* first = token.data();
    const char* last = token.data() + token.size();
    if (first != last && *first == '+') ++first;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (token.empty() || ec != std::errc() || ptr != last || std::isnan(v)) {
      fail_at_where(m_c, at, what + " (a number or inf)");
    }
    return v;
  }

  void parse_bone() {
    AsfBone bone;
    enum Key { kId, kName, kDirection, kLength, kAxis, kDof, kLimits, kBodymass, kCofmass, kEnd };
    static constexpr std::array<std::string_view, 10> kKeys = {
        "id", "name", "direction", "length", "axis", "dof", "limits", "bodymass", "cofmass", "end"};
    bool seen[kEnd] = {};
    std::string_view name_in_text;
    for (;;) {
      skip_to_content(m_c);
      const Where at = where_any(m_c);
      const std::string_view key = m_c.peek_token();
      int k = 0;
      while (k < kEnd + 1 && !iequals(key, kKeys[k])) ++k;
      if (k > kEnd) {
        m_c.fail_expected(
            "a bone keyword ('id', 'name', 'direction', 'length', 'axis', 'dof', 'limits', "
            "'bodymass', 'cofmass') or 'end'");
      }
      if (k == kEnd) {
        for (const int required : {kName, kDirection, kLength, kAxis}) {
          if (!seen[required]) {
            const std::string of = seen[kName] ? " of bone '" + bone.name + "'" : "";
            m_c.fail_expected("'" + std::string(kKeys[required]) + "' in the bone block" + of);
          }
        }
        m_c.next_token();
        expect_line_end(m_c);
        break;
      }
      if (seen[k]) fail_at_where(m_c, at, "each keyword once in a bone block", " again");
      seen[k] = true;
      m_c.next_token();
      switch (k) {
        case kId:
          bone.id = static_cast<int>(
              m_c.next_integer("a bone id (an integer)", 0, std::numeric_limits<int>::max(), true));
          break;
        case kName: {
          const Where name_at = where_inline(m_c);
          const std::string_view name = token_on_line(m_c);
          // A name starting with ':' or '#', or made of digits only, would be misread in an AMC.
          const bool digits = !name.empty() && std::all_of(name.begin(), name.end(), [](char ch) {
            return ch >= '0' && ch <= '9';
          });
          if (name.empty() || name.front() == ':' || digits) {
            fail_at_where(m_c, name_at,
                          "a bone name (not all digits, not starting with ':' or '#')");
          }
          if (iequals(name, "root")) fail_at_where(m_c, name_at, "a bone name other than 'root'");
          if (m_index.count(name)) fail_at_where(m_c, name_at, "a bone name used once", " again");
          bone.name = std::string(name);
          name_in_text = name;
          break;
        }
        case kDirection: {
          const Where dir_at = where_inline(m_c);
          bone.direction = three_numbers("bone direction");
          const double norm = bone.direction.stableNorm();
          if (!(norm > 0.0) || !std::isfinite(norm)) {
            fail_at_where(m_c, dir_at, "a non-zero direction vector");
          }
          bone.direction /= norm;
          break;
        }
        case kLength: {
          const Where len_at = where_inline(m_c);
          bone.length = m_c.next_number("bone length", true);
          if (bone.length < 0.0) fail_at_where(m_c, len_at, "a non-negative bone length");
          break;
        }
        case kAxis:
          bone.axis_angles = three_numbers("bone axis angle");
          bone.axis_order = axis_order();
          break;
        case kDof:
          bone.dofs = dof_list(true, "a dof name (rx, ry, rz, tx, ty, tz or l)");
          break;
        case kLimits: {
          if (bone.dofs.empty()) fail_at_where(m_c, at, "'dof' before 'limits'");
          const std::size_t n = bone.dofs.size();
          for (std::size_t i = 0; i < n; ++i) {
            bone.limits.push_back(limit_pair("limit " + std::to_string(i + 1) + " of " +
                                             std::to_string(n) + " (dof " +
                                             std::string(dof_name(bone.dofs[i])) + ")"));
          }
          skip_to_content(m_c);
          if (next_char(m_c) == '(') {
            m_c.fail_expected(std::to_string(n) + " limit" + (n == 1 ? "" : "s") +
                              " (one per dof)");
          }
          break;
        }
        case kBodymass:
          m_c.next_number("body mass", true);
          break;
        case kCofmass:
          m_c.next_number("centre of mass", true);
          break;
        default:
          break;
      }
      if (k != kLimits) expect_line_end(m_c);
    }
    m_index.emplace(name_in_text, static_cast<int>(m_asf.bones.size()));
    m_asf.bones.push_back(std::move(bone));
  }

  void parse_hierarchy() {
    expect_line_end(m_c);
    skip_to_content(m_c);
    if (!iequals(m_c.peek_token(), "begin")) m_c.fail_expected("'begin'");
    m_c.next_token();
    expect_line_end(m_c);
    for (;;) {
      skip_to_content(m_c);
      const Where parent_at = where_any(m_c);
      const std::string_view parent = m_c.peek_token();
      if (parent.empty() || parent.front() == ':') m_c.fail_expected("a hierarchy line or 'end'");
      m_c.next_token();
      if (iequals(parent, "end")) {
        m_hierarchy_end = parent_at;
        expect_line_end(m_c);
        return;
      }
      bool any = false;
      for (;;) {
        const Where child_at = where_inline(m_c);
        const std::string_view child = token_on_line(m_c);
        if (child.empty()) break;
        m_edges.push_back({parent, child, parent_at, child_at});
        any = true;
      }
      if (!any) m_c.fail_expected("a child bone name after '" + quote_token(parent) + "'");
    }
  }

  // Resolves the hierarchy's names, checks it is a tree hanging from the root, and orders the
  // bones depth-first (parents before children).
  void link_hierarchy() {
    const std::size_t n = m_asf.bones.size();
    std::vector<int> parent(n, -2);  // -2: not attached, -1: the root
    std::vector<std::size_t> edge_of(n, 0);
    std::vector<std::vector<int>> children(n + 1);  // children[0]: the root's, [b+1]: bone b's
    for (std::size_t e = 0; e < m_edges.size(); ++e) {
      const Edge& edge = m_edges[e];
      int p = -1;
      if (!iequals(edge.parent, "root")) {
        const auto it = m_index.find(edge.parent);
        if (it == m_index.end()) {
          fail_at_where(m_c, edge.parent_at, "'root' or a bone declared in :bonedata");
        }
        p = it->second;
      }
      const auto it = m_index.find(edge.child);
      if (it == m_index.end()) fail_at_where(m_c, edge.child_at, "a bone declared in :bonedata");
      const int child = it->second;
      if (parent[child] != -2) {
        const std::string old = parent[child] < 0 ? "root" : m_asf.bones[parent[child]].name;
        fail_at_where(m_c, edge.child_at, "a bone not attached yet",
                      " (already a child of '" + quote_token(old) + "' on line " +
                          std::to_string(m_edges[edge_of[child]].child_at.line) + ")");
      }
      parent[child] = p;
      edge_of[child] = e;
      children[p + 1].push_back(child);
    }

    // Depth-first from the root with an explicit stack (a hierarchy may be arbitrarily deep).
    std::vector<int> order;
    order.reserve(n);
    std::vector<int> stack(children[0].rbegin(), children[0].rend());
    while (!stack.empty()) {
      const int b = stack.back();
      stack.pop_back();
      order.push_back(b);
      stack.insert(stack.end(), children[b + 1].rbegin(), children[b + 1].rend());
    }
    if (order.size() != n) report_unattached(parent, edge_of, order);

    std::vector<int> new_index(n);
    for (std::size_t i = 0; i < n; ++i) new_index[order[i]] = static_cast<int>(i);
    std::vector<AsfBone> bones;
    bones.reserve(n);
    for (const int b : order) {
      bones.push_back(std::move(m_asf.bones[b]));
      bones.back().parent = parent[b] < 0 ? -1 : new_index[parent[b]];
    }
    m_asf.bones = std::move(bones);
  }

  [[noreturn]] void report_unattached(const std::vector<int>& parent,
                                      const std::vector<std::size_t>& edge_of,
                                      const std::vector<int>& reached) {
    const std::size_t n = parent.size();
    std::vector<char> seen(n, 0);
    for (const int b : reached) seen[b] = 1;
    int b = 0;
    while (seen[b]) ++b;
    // Walk up from the first unreached bone: either a bone without a parent, or a cycle.
    std::vector<char> on_path(n, 0);
    std::vector<int> path;
    while (parent[b] >= 0 && !on_path[b]) {
      on_path[b] = 1;
      path.push_back(b);
      b = parent[b];
    }
    if (parent[b] == -2) {
      fail_at_where(m_c, m_hierarchy_end,
                    "a hierarchy line attaching bone '" + quote_token(m_asf.bones[b].name) + "'");
    }
    // b is on a cycle: name it, b → its parent → … → b (a few names at most).
    std::string cycle = quote_token(m_asf.bones[b].name);
    int x = parent[b];
    for (int shown = 0; shown < 8 && x != b; ++shown, x = parent[x]) {
      cycle += " -> " + quote_token(m_asf.bones[x].name);
    }
    cycle += x == b ? " -> " + quote_token(m_asf.bones[b].name) : " -> ...";
    fail_at_where(m_c, m_edges[edge_of[b]].child_at, "a bone connected to 'root'",
                  " (in a cycle, each a child of the next: " + cycle + ")");
  }

  TextCursor m_c;
  AsfSkeleton m_asf;
  bool m_seen[8] = {};
  std::unordered_map<std::string_view, int> m_index;  // names point into the text
  std::vector<Edge> m_edges;
  Where m_hierarchy_end{};
};

// ---------------------------------------------------------------------------------------------
// AMC

// Per-joint conversion data, joint 0 = root, joint b+1 = bone b.
struct JointDofs {
  std::vector<Dof> dofs;
  Eigen::Quaterniond c = Eigen::Quaterniond::Identity();  // the `axis` (root: `orientation`)
  Eigen::Matrix3d c_matrix = Eigen::Matrix3d::Identity();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // for `l`
  std::vector<int> children;                            // joints moved by `l`
};

void check_parents(const AsfSkeleton& asf) {
  for (std::size_t i = 0; i < asf.bones.size(); ++i) {
    const int p = asf.bones[i].parent;
    if (p < -1 || p >= static_cast<int>(i)) {
      throw ParameterError("ASF bone '" + asf.bones[i].name + "' (index " + std::to_string(i) +
                           ") has parent index " + std::to_string(p) +
                           ": parents must come before their children");
    }
  }
}

}  // namespace

AsfSkeleton parse_asf(std::string_view text, const std::string& path) {
  return AsfParser(text, path).parse();
}

AsfSkeleton read_asf(const std::string& path) {
  return parse_asf(read_text_file(path), path);
}

Skeleton asf_to_skeleton(const AsfSkeleton& asf) {
  check_parents(asf);
  using C = ChannelType;
  const std::vector<C> positions{C::Xposition, C::Yposition, C::Zposition};
  const std::vector<C> rotations{C::Zrotation, C::Yrotation, C::Xrotation};
  Skeleton skel;
  skel.joints.resize(asf.bones.size() + 1);
  Joint& root = skel.joints[0];
  root.name = "root";
  root.offset = asf.root_position;
  root.channels = positions;
  root.channels.insert(root.channels.end(), rotations.begin(), rotations.end());

  std::vector<bool> has_children(asf.bones.size(), false);
  for (const AsfBone& bone : asf.bones) {
    if (bone.parent >= 0) has_children[bone.parent] = true;
  }
  for (std::size_t i = 0; i < asf.bones.size(); ++i) {
    const AsfBone& bone = asf.bones[i];
    Joint& joint = skel.joints[i + 1];
    joint.name = bone.name;
    joint.parent = bone.parent + 1;
    if (bone.parent >= 0) {
      const AsfBone& p = asf.bones[bone.parent];
      joint.offset = p.direction * p.length;
    }
    const auto has = [](const AsfBone& b, bool (*pred)(Dof)) {
      return std::any_of(b.dofs.begin(), b.dofs.end(), pred);
    };
    const bool stretched_parent =
        bone.parent >= 0 && has(asf.bones[bone.parent], [](Dof d) { return d == Dof::L; });
    if (has(bone, is_translation) || stretched_parent) joint.channels = positions;
    if (has(bone, is_rotation)) {
      joint.channels.insert(joint.channels.end(), rotations.begin(), rotations.end());
    }
    if (!has_children[i]) joint.end_sites.push_back(bone.direction * bone.length);
  }
  return skel;
}

Motion parse_amc(std::string_view text, const AsfSkeleton& asf, double fps,
                 const std::string& path) {
  if (!(fps > 0.0) || !std::isfinite(fps)) {
    throw ParameterError("AMC frame rate must be positive and finite, got " + std::to_string(fps));
  }
  const Skeleton skel = asf_to_skeleton(asf);
  const int joints = skel.num_joints();

  std::vector<JointDofs> info(joints);
  std::unordered_map<std::string_view, int> index;
  info[0].dofs = asf.root_order;
  index.emplace("root", 0);
  for (int j = 1; j < joints; ++j) {
    const AsfBone& bone = asf.bones[j - 1];
    info[j].dofs = bone.dofs;
    info[j].direction = bone.direction;
    index.emplace(bone.name, j);
    if (bone.parent >= 0) info[bone.parent + 1].children.push_back(j);
  }
  const double asf_angle = asf.angles_in_degrees ? deg_to_rad(1.0) : 1.0;
  const auto rest_rotation = [&](const std::array<Axis, 3>& order, const Eigen::Vector3d& xyz) {
    return acclaim_euler(order, axis_angles_in_order(order, xyz) * asf_angle);
  };
  info[0].c = rest_rotation(asf.root_axis_order, asf.root_orientation);
  for (int j = 1; j < joints; ++j) {
    info[j].c = rest_rotation(asf.bones[j - 1].axis_order, asf.bones[j - 1].axis_angles);
  }
  for (auto& d : info) d.c_matrix = d.c.toRotationMatrix();

  Motion motion;
  motion.frame_time = 1.0 / fps;
  motion.num_joints = joints;
  std::vector<Eigen::Vector3d> rest(joints);
  for (int j = 0; j < joints; ++j) rest[j] = skel.joints[j].offset;

  TextCursor c(text, path);
  double amc_angle = asf_angle;
  bool unit_declared = false;
  long long frame_number = -1;
  std::vector<int> seen_in_frame(joints, -1);
  std::vector<double> values;
  std::vector<Axis> rot_axes;
  std::vector<double> rot_angles;

  while (skip_to_content(c)) {
    const Where at = where_any(c);
    const std::string_view token = c.peek_token();
    if (token.front() == ':') {
      if (motion.num_frames > 0) c.fail_expected("a frame number or a bone line");
      if (iequals(token, ":FULLY-SPECIFIED")) {
        // Every frame lists every bone; nothing to do (absent bones would keep their rest pose).
      } else if (iequals(token, ":DEGREES") || iequals(token, ":RADIANS")) {
        const double unit = iequals(token, ":DEGREES") ? deg_to_rad(1.0) : 1.0;
        if (unit_declared && unit != amc_angle) fail_at_where(c, at, "one angle unit");
        amc_angle = unit;
        unit_declared = true;
      } else {
        c.fail_expected("':FULLY-SPECIFIED', ':DEGREES' or ':RADIANS'");
      }
      c.next_token();
      expect_line_end(c);
      continue;
    }
    if (std::all_of(token.begin(), token.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) {
      const long long n =
          c.next_integer("a frame number", 0, std::numeric_limits<int>::max(), true);
      if (frame_number >= 0 && n != frame_number + 1) {
        fail_at_where(c, at, "frame number " + std::to_string(frame_number + 1));
      }
      expect_line_end(c, "end of line after the frame number");
      if (motion.num_frames == std::numeric_limits<int>::max()) {
        fail_at_where(c, at, "at most " + std::to_string(motion.num_frames) + " frames");
      }
      frame_number = n;
      // A new frame starts at the rest pose; bone lines overwrite it (rows grow with the file).
      motion.rotations.insert(motion.rotations.end(), joints, Eigen::Quaterniond::Identity());
      motion.translations.insert(motion.translations.end(), rest.begin(), rest.end());
      ++motion.num_frames;
      continue;
    }
    if (motion.num_frames == 0) c.fail_expected("a frame number");
    const auto it = index.find(token);
    if (it == index.end()) c.fail_expected("a bone of the skeleton or a frame number");
    const int j = it->second;
    if (seen_in_frame[j] == motion.num_frames) {
      fail_at_where(c, at, "each bone once per frame",
                    " again in frame " + std::to_string(frame_number));
    }
    seen_in_frame[j] = motion.num_frames;
    c.next_token();

    const JointDofs& d = info[j];
    values.clear();
    for (std::size_t k = 0; k < d.dofs.size(); ++k) {
      values.push_back(number_on_line(c, [&] {
        return "value " + std::to_string(k + 1) + " of " + std::to_string(d.dofs.size()) +
               " for '" + quote_token(token) + "' (" + std::string(dof_name(d.dofs[k])) + ")";
      }));
    }
    if (!at_line_end_or_comment(c)) {
      c.fail_expected("end of line after the " + std::to_string(d.dofs.size()) + " values of '" +
                      quote_token(token) + "'");
    }

    const std::size_t base = static_cast<std::size_t>(motion.num_frames - 1) * joints;
    rot_axes.clear();
    rot_angles.clear();
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    double stretch = 0.0;
    for (std::size_t k = 0; k < d.dofs.size(); ++k) {
      const Dof dof = d.dofs[k];
      if (is_rotation(dof)) {
        // First listed, first applied: R = R(last)·…·R(first).
        rot_axes.insert(rot_axes.begin(), static_cast<Axis>(dof_axis(dof)));
        rot_angles.insert(rot_angles.begin(), values[k] * amc_angle);
      } else if (is_translation(dof)) {
        if (j == 0) {
          motion.translations[base][dof_axis(dof)] = values[k];  // replaces `position`
        } else {
          shift[dof_axis(dof)] = values[k];
        }
      } else {
        stretch = values[k];
      }
    }
    if (!rot_axes.empty()) {
      motion.rotations[base + j] =
          (d.c * euler_to_quat(rot_axes, rot_angles) * d.c.conjugate()).normalized();
    }
    if (j > 0) {
      // Increments, so a child's own tx ty tz and its parent's `l` add up in any line order.
      motion.translations[base + j] += d.c_matrix * shift;
      for (const int child : d.children) {
        motion.translations[base + child] += d.direction * stretch;
      }
    }
  }
  if (motion.num_frames == 0) c.fail_expected("a frame number");
  return motion;
}

Clip load_asf_amc(const std::string& asf_path, const std::string& amc_path, double fps) {
  AsfSkeleton asf = read_asf(asf_path);
  Clip clip;
  clip.path = amc_path;
  clip.motion = parse_amc(read_text_file(amc_path), asf, fps, amc_path);
  clip.skeleton = asf_to_skeleton(asf);
  clip.warnings = std::move(asf.warnings);
  return clip;
}

}  // namespace motionmap::io
