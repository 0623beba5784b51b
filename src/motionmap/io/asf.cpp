#include "motionmap/io/asf.h"

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
#include "motionmap/io/detail/acclaim.h"

namespace motionmap::io {

namespace {

using Mark = TextCursor::Mark;

// ASF is line-oriented, with `#` comments (whole lines or line tails).
constexpr char kComment = '#';

std::optional<Dof> parse_dof(std::string_view s) {
  for (int d = 0; d <= static_cast<int>(Dof::L); ++d) {
    if (ascii_iequals(s, dof_name(static_cast<Dof>(d)))) return static_cast<Dof>(d);
  }
  return std::nullopt;
}

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

constexpr std::string_view kSections =
    "a section (':version', ':name', ':units', ':documentation', ':root', ':bonedata', "
    "':hierarchy')";

class AsfParser {
 public:
  AsfParser(std::string_view text, const std::string& path) : m_c(text, path) {}

  AsfSkeleton parse() {
    bool any = false;
    while (m_c.skip_to_content(kComment)) {
      const std::string_view token = m_c.peek_token();
      if (token.front() != ':') m_c.fail_expected(kSections);
      const Mark at = m_c.mark_next();
      const int section = section_index(token);
      if (section < 0) m_c.fail_expected(kSections);
      if (m_seen[section]) m_c.fail_expected_at(at, "each section once", " again");
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
    Mark parent_at, child_at;
  };

  static int section_index(std::string_view token) {
    for (std::size_t i = 0; i < kSectionNames.size(); ++i) {
      if (ascii_iequals(token, kSectionNames[i])) return static_cast<int>(i);
    }
    return -1;
  }

  // True when the cursor is at the end or at the next `:section` line.
  bool at_section_end() { return !m_c.skip_to_content(kComment) || m_c.peek_char() == ':'; }

  void skip_section_body() {
    m_c.rest_of_line();
    for (;;) {
      m_c.skip_space();
      if (m_c.at_end() || m_c.peek_char() == ':') return;
      m_c.skip_line();
    }
  }

  void parse_name() { m_asf.name = std::string(trim_blanks(m_c.rest_of_line())); }

  double positive_number(std::string_view what) {
    const Mark at = m_c.mark_next_on_line();
    const double v = m_c.next_number(what, true);
    if (!(v > 0.0)) m_c.fail_expected_at(at, "a positive " + std::string(what));
    return v;
  }

  void parse_units() {
    while (!at_section_end()) {
      const std::string_view key = m_c.peek_token();
      if (ascii_iequals(key, "mass")) {
        m_c.next_token();
        m_asf.mass_unit = positive_number("mass unit");
      } else if (ascii_iequals(key, "length")) {
        m_c.next_token();
        m_asf.length_unit = positive_number("length unit");
      } else if (ascii_iequals(key, "angle")) {
        m_c.next_token();
        const Mark at = m_c.mark_next_on_line();
        const std::string_view unit = m_c.next_token_on_line(kComment);
        if (ascii_iequals(unit, "deg")) {
          m_asf.angles_in_degrees = true;
        } else if (ascii_iequals(unit, "rad")) {
          m_asf.angles_in_degrees = false;
        } else {
          m_c.fail_expected_at(at, "an angle unit ('deg' or 'rad')");
        }
      } else {
        m_c.fail_expected("a unit ('mass', 'length' or 'angle') or a section");
      }
      m_c.expect_line_end(kComment);
    }
  }

  Eigen::Vector3d three_numbers(std::string_view what) {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = m_c.next_number(what, true);
    return v;
  }

  std::array<Axis, 3> axis_order() {
    const Mark at = m_c.mark_next_on_line();
    const auto order = parse_axis_order(m_c.next_token_on_line(kComment));
    if (!order) m_c.fail_expected_at(at, "an axis order (a permutation of XYZ)");
    return *order;
  }

  // Dof names up to the end of the line, each at most once, at least one.
  std::vector<Dof> dof_list(bool allow_length, std::string_view expected) {
    std::vector<Dof> dofs;
    for (;;) {
      const Mark at = m_c.mark_next_on_line();
      const std::string_view token = m_c.next_token_on_line(kComment);
      if (token.empty() && !dofs.empty()) return dofs;
      const auto dof = parse_dof(token);
      if (!dof || (!allow_length && *dof == Dof::L))
        m_c.fail_expected_at(at, std::string(expected));
      if (std::find(dofs.begin(), dofs.end(), *dof) != dofs.end()) {
        m_c.fail_expected_at(at, "each dof once", " again");
      }
      dofs.push_back(*dof);
    }
  }

  void parse_root() {
    bool seen[4] = {false, false, false, false};
    static constexpr std::array<std::string_view, 4> kKeys = {"order", "axis", "position",
                                                              "orientation"};
    while (!at_section_end()) {
      const Mark at = m_c.mark_next();
      const std::string_view key = m_c.peek_token();
      int k = 0;
      while (k < 4 && !ascii_iequals(key, kKeys[k])) ++k;
      if (k == 4) {
        m_c.fail_expected(
            "a root keyword ('order', 'axis', 'position', 'orientation') or a section");
      }
      if (seen[k]) m_c.fail_expected_at(at, "each root keyword once", " again");
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
      m_c.expect_line_end(kComment);
    }
    if (!seen[0]) m_c.fail_expected("'order' in the :root section");
  }

  void parse_bonedata() {
    while (!at_section_end()) {
      if (!ascii_iequals(m_c.peek_token(), "begin")) m_c.fail_expected("'begin' or a section");
      m_c.next_token();
      m_c.expect_line_end(kComment);
      parse_bone();
    }
  }

  // A `(min max)` pair of a `limits` list; the parentheses may stick to the numbers or stand
  // alone, pairs may span lines. Limits may be ±inf.
  std::pair<double, double> limit_pair(const std::string& what) {
    Mark at = m_c.mark_next();
    std::string_view token = m_c.next_token();
    if (token.empty() || token.front() != '(') m_c.fail_expected_at(at, "'(' opening " + what);
    token.remove_prefix(1);
    if (token.empty()) {
      at = m_c.mark_next();
      token = m_c.next_token();
    } else {
      ++at.pos;  // the number after the '('
    }
    const double low = limit_number(token, at, "the lower " + what);
    at = m_c.mark_next();
    token = m_c.next_token();
    const bool closed = !token.empty() && token.back() == ')';
    if (closed) token.remove_suffix(1);
    const double high = limit_number(token, at, "the upper " + what);
    if (!closed) {
      at = m_c.mark_next();
      if (m_c.next_token() != ")") m_c.fail_expected_at(at, "')' closing " + what);
    }
    return {low, high};
  }

  double limit_number(std::string_view token, const Mark& at, const std::string& what) {
    const char* first = token.data();
    const char* last = token.data() + token.size();
    if (first != last && *first == '+') ++first;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (token.empty() || ec != std::errc() || ptr != last || std::isnan(v)) {
      m_c.fail_expected_at(at, what + " (a number or inf)");
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
      m_c.skip_to_content(kComment);
      const Mark at = m_c.mark_next();
      const std::string_view key = m_c.peek_token();
      int k = 0;
      while (k < kEnd + 1 && !ascii_iequals(key, kKeys[k])) ++k;
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
        m_c.expect_line_end(kComment);
        break;
      }
      if (seen[k]) m_c.fail_expected_at(at, "each keyword once in a bone block", " again");
      seen[k] = true;
      m_c.next_token();
      switch (k) {
        case kId:
          bone.id = static_cast<int>(
              m_c.next_integer("a bone id (an integer)", 0, std::numeric_limits<int>::max(), true));
          break;
        case kName: {
          const Mark name_at = m_c.mark_next_on_line();
          const std::string_view name = m_c.next_token_on_line(kComment);
          // A name starting with ':' or '#', or made of digits only, would be misread in an AMC.
          if (name.empty() || name.front() == ':' || all_digits(name)) {
            m_c.fail_expected_at(name_at,
                                 "a bone name (not all digits, not starting with ':' or '#')");
          }
          if (ascii_iequals(name, "root"))
            m_c.fail_expected_at(name_at, "a bone name other than 'root'");
          if (m_index.count(name)) m_c.fail_expected_at(name_at, "a bone name used once", " again");
          bone.name = std::string(name);
          name_in_text = name;
          break;
        }
        case kDirection: {
          const Mark dir_at = m_c.mark_next_on_line();
          bone.direction = three_numbers("bone direction");
          const double norm = bone.direction.stableNorm();
          if (!(norm > 0.0) || !std::isfinite(norm)) {
            m_c.fail_expected_at(dir_at, "a non-zero direction vector");
          }
          bone.direction /= norm;
          break;
        }
        case kLength: {
          const Mark len_at = m_c.mark_next_on_line();
          bone.length = m_c.next_number("bone length", true);
          if (bone.length < 0.0) m_c.fail_expected_at(len_at, "a non-negative bone length");
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
          if (bone.dofs.empty()) m_c.fail_expected_at(at, "'dof' before 'limits'");
          const std::size_t n = bone.dofs.size();
          for (std::size_t i = 0; i < n; ++i) {
            bone.limits.push_back(limit_pair("limit " + std::to_string(i + 1) + " of " +
                                             std::to_string(n) + " (dof " +
                                             std::string(dof_name(bone.dofs[i])) + ")"));
          }
          m_c.skip_to_content(kComment);
          if (m_c.peek_char() == '(') {
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
      if (k != kLimits) m_c.expect_line_end(kComment);
    }
    m_index.emplace(name_in_text, static_cast<int>(m_asf.bones.size()));
    m_asf.bones.push_back(std::move(bone));
  }

  void parse_hierarchy() {
    m_c.expect_line_end(kComment);
    m_c.skip_to_content(kComment);
    if (!ascii_iequals(m_c.peek_token(), "begin")) m_c.fail_expected("'begin'");
    m_c.next_token();
    m_c.expect_line_end(kComment);
    for (;;) {
      m_c.skip_to_content(kComment);
      const Mark parent_at = m_c.mark_next();
      const std::string_view parent = m_c.peek_token();
      if (parent.empty() || parent.front() == ':') m_c.fail_expected("a hierarchy line or 'end'");
      m_c.next_token();
      if (ascii_iequals(parent, "end")) {
        m_hierarchy_end = parent_at;
        m_c.expect_line_end(kComment);
        return;
      }
      bool any = false;
      for (;;) {
        const Mark child_at = m_c.mark_next_on_line();
        const std::string_view child = m_c.next_token_on_line(kComment);
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
      if (!ascii_iequals(edge.parent, "root")) {
        const auto it = m_index.find(edge.parent);
        if (it == m_index.end()) {
          m_c.fail_expected_at(edge.parent_at, "'root' or a bone declared in :bonedata");
        }
        p = it->second;
      }
      const auto it = m_index.find(edge.child);
      if (it == m_index.end()) m_c.fail_expected_at(edge.child_at, "a bone declared in :bonedata");
      const int child = it->second;
      if (parent[child] != -2) {
        const std::string old = parent[child] < 0 ? "root" : m_asf.bones[parent[child]].name;
        m_c.fail_expected_at(edge.child_at, "a bone not attached yet",
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
      m_c.fail_expected_at(m_hierarchy_end, "a hierarchy line attaching bone '" +
                                                quote_token(m_asf.bones[b].name) + "'");
    }
    // b is on a cycle: name it, b → its parent → … → b (a few names at most).
    std::string cycle = quote_token(m_asf.bones[b].name);
    int x = parent[b];
    for (int shown = 0; shown < 8 && x != b; ++shown, x = parent[x]) {
      cycle += " -> " + quote_token(m_asf.bones[x].name);
    }
    cycle += x == b ? " -> " + quote_token(m_asf.bones[b].name) : " -> ...";
    m_c.fail_expected_at(m_edges[edge_of[b]].child_at, "a bone connected to 'root'",
                         " (in a cycle, each a child of the next: " + cycle + ")");
  }

  TextCursor m_c;
  AsfSkeleton m_asf;
  bool m_seen[8] = {};
  std::unordered_map<std::string_view, int> m_index;  // names point into the text
  std::vector<Edge> m_edges;
  Mark m_hierarchy_end{};
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

}  // namespace motionmap::io
