#include "motionmap/io/bvh.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <ostream>
#include <unordered_map>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/rotation.h"
#include "motionmap/core/text_cursor.h"

namespace motionmap::io {

namespace {

// #frames·#joints a file may declare without one byte of motion text per transform (~235 MB of
// Motion); real files have ~20 bytes per transform.
constexpr unsigned long long kFreeTransforms = 1ull << 22;

constexpr std::string_view kChannelNames =
    "a channel name (Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)";

std::string_view trim_trailing_blanks(std::string_view s) {
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

// "1 more frame", "6 more values".
std::string more(long long n, const std::string& noun) {
  return std::to_string(n) + " more " + noun + (n == 1 ? "" : "s");
}

// Reads one BVH text. The hierarchy is parsed iteratively (a stack of open joints, capped at
// kBvhMaxDepth) so hostile nesting cannot overflow the call stack; the motion block is scanned
// row by row with from_chars straight from the text, which is where nearly all the time goes.
// Where the text runs out, the error says "file ends early: expected <what is missing>" at the end
// of the file instead of describing a next token that is not there.
class BvhParser {
 public:
  BvhParser(std::string_view text, const std::string& path) : m_cur(text, path) {}

  BvhDocument parse() {
    parse_hierarchy();
    parse_motion();
    return std::move(m_doc);
  }

 private:
  struct OpenJoint {
    int index = 0;
    TextCursor::Mark keyword;    // where its ROOT/JOINT keyword starts
    TextCursor::Mark name;       // where its name starts
    bool zero_channels = false;  // declared with `CHANNELS 0`
    std::size_t first_use = 0;   // the line of an earlier joint of the same name; 0: none
  };

  // True when nothing but whitespace is left from the cursor on (stops at the first other byte).
  bool only_space_left() const {
    const std::string_view rest = m_cur.text().substr(m_cur.position());
    return std::all_of(rest.begin(), rest.end(), is_space);
  }

  // `path:line:col: error: file ends early: expected <expected>`, at the end of the text.
  [[noreturn]] void fail_early(const std::string& expected) {
    m_cur.skip_space();
    m_cur.fail_at(m_cur.line(), m_cur.column(), "file ends early: expected " + expected);
  }

  // Fails at the next token; if the text has run out, says so, naming `at_end` (or `expected`).
  // A file cut inside one of the quoted keywords of `expected` (`'CHANNELS'` cut to `C`) has run
  // out too.
  [[noreturn]] void fail(const std::string& expected, const std::string& at_end = {}) {
    if (only_space_left() || cut_inside(quoted_words(expected))) {
      fail_early(at_end.empty() ? expected : at_end);
    }
    m_cur.fail_expected(expected);
  }

  // The 'quoted' words of an expected-list: "'JOINT', 'End Site' or '}'" gives JOINT, End Site, }.
  static std::vector<std::string_view> quoted_words(std::string_view expected) {
    std::vector<std::string_view> words;
    for (std::size_t open = expected.find('\''); open != std::string_view::npos;) {
      const std::size_t close = expected.find('\'', open + 1);
      if (close == std::string_view::npos) break;
      words.push_back(expected.substr(open + 1, close - open - 1));
      open = expected.find('\'', close + 1);
    }
    return words;
  }

  // True when the next token is the last thing in the text and a strict prefix of one of `words`:
  // the file was cut inside that word. The cursor is then left at the end of the text.
  bool cut_inside(const std::vector<std::string_view>& words) {
    const TextCursor::Mark at = m_cur.mark();
    const std::string_view token = m_cur.peek_token();
    const bool prefix = !token.empty() && std::any_of(words.begin(), words.end(), [&](auto w) {
      return w.size() > token.size() && w.substr(0, token.size()) == token;
    });
    if (prefix) {
      m_cur.next_token();
      if (only_space_left()) return true;
    }
    m_cur.reset(at);
    return false;
  }

  // Before a number or count that must be on the current line: the text may not end there.
  void fail_if_file_ends(const std::string& what) {
    m_cur.skip_inline_space();
    if (m_cur.at_line_end() && only_space_left()) fail_early(what);
  }

  void warn(const TextCursor::Mark& at, const std::string& message) {
    m_doc.warnings.push_back(m_cur.path() + ":" + std::to_string(at.line) + ":" +
                             std::to_string(at.pos - at.line_start + 1) + ": warning: " + message);
  }

  std::string joint_label(int j) const {
    return "joint '" + quote_token(m_doc.skeleton.joints[j].name) + "'";
  }

  void parse_hierarchy() {
    if (cut_inside({"HIERARCHY"})) fail_early("'HIERARCHY'");
    m_cur.expect("HIERARCHY");
    for (;;) {
      const std::string_view token = m_cur.peek_token();
      const TextCursor::Mark keyword = m_cur.mark();
      if (token == "ROOT" || token == "JOINT") {
        // Some exporters open the hierarchy with JOINT: it can only be a root.
        if (token == "JOINT") {
          warn(keyword, "root declared with JOINT instead of ROOT; read as ROOT");
        }
        m_cur.next_token();
        begin_joint(-1, keyword);
        parse_joint_bodies();
      } else if (token == "MOTION" && !m_doc.skeleton.joints.empty()) {
        return;
      } else if (cut_inside({"ROOT", "JOINT", "MOTION"})) {
        fail_early(m_doc.skeleton.joints.empty() ? "'ROOT'" : "'MOTION'");
      } else if (m_doc.skeleton.joints.empty()) {
        fail("'ROOT'");
      } else {
        fail("'ROOT' or 'MOTION'", "'MOTION'");
      }
    }
  }

  // Children, End Sites and closing braces until the root just opened is closed.
  void parse_joint_bodies() {
    while (!m_open.empty()) {
      const std::string_view token = m_cur.peek_token();
      const TextCursor::Mark at = m_cur.mark();
      const int joint = m_open.back().index;
      if (token == "JOINT") {
        m_cur.next_token();
        begin_joint(joint, at);
      } else if (token == "End") {
        m_cur.next_token();
        if (m_cur.peek_token() != "Site") fail("'Site'");
        m_cur.next_token();
        if (m_cur.peek_token() != "{") {
          fail("'{'", "'{' opening an End Site of " + joint_label(joint));
        }
        m_cur.next_token();
        if (m_cur.peek_token() != "OFFSET") {
          fail("'OFFSET'", "'OFFSET' of an End Site of " + joint_label(joint));
        }
        const Eigen::Vector3d offset = read_offset();
        if (m_cur.peek_token() != "}") {
          fail("'}'", "'}' closing an End Site of " + joint_label(joint));
        }
        m_cur.next_token();
        m_doc.skeleton.joints[joint].end_sites.push_back(offset);
      } else if (token == "}") {
        m_cur.next_token();
        close_joint();
      } else {
        fail("'JOINT', 'End Site' or '}'", "'}' closing " + joint_label(joint));
      }
    }
  }

  // Pops the innermost open joint. A leaf JOINT declared with `CHANNELS 0` (no child joints, no
  // End Sites) is how some exporters write an End Site: it becomes one of its parent's, offset
  // kept, as if the file had said `End Site { OFFSET ... }`. With children it is a static joint.
  void close_joint() {
    const OpenJoint open = m_open.back();
    m_open.pop_back();
    std::vector<Joint>& joints = m_doc.skeleton.joints;
    const Joint& joint = joints[open.index];
    const bool leaf = open.index + 1 == static_cast<int>(joints.size()) && joint.end_sites.empty();
    if (!open.zero_channels || !leaf || joint.parent < 0) {
      // A joint that stays one needs a name of its own. Checked here, not where the name is read,
      // because end sites written as `JOINT Site { ... CHANNELS 0 }` share theirs.
      if (open.first_use != 0) {
        m_cur.reset(open.name);
        m_cur.fail_expected("a joint name not used before (line " + std::to_string(open.first_use) +
                            ")");
      }
      return;
    }
    warn(open.keyword,
         joint_label(open.index) + " has CHANNELS 0 and no children; read as an end site");
    // An end site's name is no joint's: a later joint may use it.
    if (open.first_use == 0) m_name_lines.erase(joint.name);
    joints[joint.parent].end_sites.push_back(joint.offset);
    joints.pop_back();
  }

  // After ROOT/JOINT: the name, '{', OFFSET and CHANNELS (either order, CHANNELS optional).
  void begin_joint(int parent, const TextCursor::Mark& keyword) {
    if (m_open.size() >= static_cast<std::size_t>(kBvhMaxDepth)) {
      m_cur.reset(keyword);
      m_cur.fail_expected("at most " + std::to_string(kBvhMaxDepth) + " nested joints");
    }
    Joint joint;
    joint.parent = parent;
    m_cur.skip_inline_space();
    const TextCursor::Mark name_at = m_cur.mark();
    joint.name = read_name();
    const auto [earlier, inserted] = m_name_lines.emplace(joint.name, name_at.line);
    const std::size_t first_use = inserted ? 0 : earlier->second;
    if (m_cur.peek_token() != "{") {
      fail("'{'", "'{' opening joint '" + quote_token(joint.name) + "'");
    }
    m_cur.next_token();
    bool have_offset = false;
    bool have_channels = false;
    for (;;) {
      const std::string_view token = m_cur.peek_token();
      if (token == "OFFSET" && !have_offset) {
        joint.offset = read_offset();
        have_offset = true;
      } else if (token == "CHANNELS" && !have_channels) {
        read_channels(joint);
        have_channels = true;
      } else {
        break;
      }
    }
    if (!have_offset) fail("'OFFSET'", "'OFFSET' of joint '" + quote_token(joint.name) + "'");
    if (!have_channels && cut_inside({"CHANNELS"})) {
      fail_early("'CHANNELS' of joint '" + quote_token(joint.name) + "'");
    }
    m_open.push_back({m_doc.skeleton.num_joints(), keyword, name_at,
                      have_channels && joint.channels.empty(), first_use});
    m_doc.skeleton.joints.push_back(std::move(joint));
  }

  // The rest of the line, so names may hold ':' or spaces; a trailing " {" is left for expect().
  std::string read_name() {
    m_cur.skip_inline_space();
    const TextCursor::Mark at = m_cur.mark();
    std::string_view name = trim_trailing_blanks(m_cur.rest_of_line());
    if (!name.empty() && name.back() == '{') {
      const std::string_view head = trim_trailing_blanks(name.substr(0, name.size() - 1));
      if (head.size() + 1 < name.size() || head.empty()) {
        m_cur.reset({at.pos + name.size() - 1, at.line, at.line_start});
        name = head;
      }
    }
    if (name.empty()) {
      m_cur.reset(at);
      fail("a joint name");
    }
    return std::string(name);
  }

  Eigen::Vector3d read_offset() {
    m_cur.next_token();  // OFFSET
    Eigen::Vector3d offset;
    offset.x() = number_on_line("OFFSET x");
    offset.y() = number_on_line("OFFSET y");
    offset.z() = number_on_line("OFFSET z");
    check_no_more_numbers("only 3 OFFSET values");
    return offset;
  }

  double number_on_line(const std::string& what) {
    fail_if_file_ends(what);
    return m_cur.next_number(what, true);
  }

  void read_channels(Joint& joint) {
    m_cur.next_token();  // CHANNELS
    fail_if_file_ends("a channel count");
    const TextCursor::Mark count_at = m_cur.mark();
    const long long count = m_cur.next_integer("a channel count", 0, INT_MAX, true);
    if (m_total_channels + count > INT_MAX) {
      m_cur.reset(count_at);
      m_cur.fail_expected("a channel count (at most " + std::to_string(INT_MAX) + " in all)");
    }
    m_total_channels += count;
    // Names are read one by one, so a huge count cannot allocate more than the line holds.
    for (long long i = 0; i < count; ++i) {
      m_cur.skip_inline_space();
      const TextCursor::Mark at = m_cur.mark();
      const auto channel = parse_channel_name(m_cur.next_token_on_line());
      if (!channel) {
        m_cur.reset(at);
        if (m_cur.at_line_end() || cut_inside({"Xposition", "Yposition", "Zposition", "Xrotation",
                                               "Yrotation", "Zrotation"})) {
          fail(std::to_string(count) + " channel names as CHANNELS declares");
        }
        m_cur.fail_expected(kChannelNames);
      }
      joint.channels.push_back(*channel);
    }
    m_cur.skip_inline_space();
    const TextCursor::Mark after = m_cur.mark();
    if (parse_channel_name(m_cur.next_token_on_line())) {
      m_cur.reset(after);
      m_cur.fail_expected("only " + std::to_string(count) + " channel names as CHANNELS declares");
    }
    m_cur.reset(after);
  }

  // A number left on the line is an error; anything else is for the caller to judge.
  void check_no_more_numbers(const std::string& expected) {
    m_cur.skip_inline_space();
    const char* first = m_cur.text().data() + m_cur.position();
    const char* last = m_cur.text().data() + m_cur.text().size();
    double ignored = 0.0;
    if (!m_cur.at_line_end() && parse_number(first, last, ignored) != NumberStatus::NotANumber) {
      m_cur.fail_expected(expected);
    }
  }

  void parse_motion() {
    m_cur.expect("MOTION");
    if (m_cur.peek_token() != "Frames:") fail("'Frames:'");
    m_cur.next_token();
    fail_if_file_ends("a frame count");
    const TextCursor::Mark frames_at = m_cur.mark();
    const long long frames = m_cur.next_integer("a frame count", 0, INT_MAX, true);
    if (m_cur.peek_token() != "Frame") fail("'Frame'", "'Frame Time:'");
    m_cur.next_token();
    if (m_cur.peek_token() != "Time:") fail("'Time:'", "'Frame Time:'");
    m_cur.next_token();
    fail_if_file_ends("a frame time");
    const TextCursor::Mark time_at = m_cur.mark();
    const double frame_time = m_cur.next_number("a frame time", true);
    if (!(frame_time > 0.0)) {
      m_cur.reset(time_at);
      m_cur.fail_expected("a frame time > 0");
    }
    m_cur.skip_inline_space();
    if (!m_cur.at_line_end()) m_cur.fail_expected("end of line after the frame time");
    m_cur.consume_line_end();

    // Before allocating: every value takes at least 2 bytes (a digit and a separator, the last
    // one maybe none), every row of a skeleton without channels at least its line end. Both
    // factors are < 2^31, so the products cannot overflow 64 bits.
    const auto channels = static_cast<unsigned long long>(m_doc.skeleton.num_channels());
    const auto count = static_cast<unsigned long long>(frames) * channels;
    const unsigned long long remaining = m_cur.remaining();
    const unsigned long long least =
        channels == 0 ? static_cast<unsigned long long>(frames) : (count == 0 ? 0 : 2 * count - 1);
    if (least > remaining) {
      // The rows cannot all be there. Read them without storing anything, so that a file which
      // ends early (or has a bad row first) is reported as such, where it happens.
      if (channels > 0) parse_rows<false>(static_cast<int>(frames), static_cast<int>(channels));
      m_cur.reset(frames_at);
      m_cur.fail_expected("a frame count the rest of the file can hold (" + std::to_string(frames) +
                          " frames of " + std::to_string(channels) + " values need at least " +
                          std::to_string(least) + " bytes, " + std::to_string(remaining) +
                          " remain)");
    }
    // to_motion() makes #frames·#joints transforms: many joints without channels would let a
    // small file ask for gigabytes. Beyond kFreeTransforms, a byte per transform is required.
    const auto joints = static_cast<unsigned long long>(m_doc.skeleton.num_joints());
    const auto transforms = static_cast<unsigned long long>(frames) * joints;
    if (transforms > kFreeTransforms && transforms > remaining) {
      m_cur.reset(frames_at);
      m_cur.fail_expected("a frame count the rest of the file can hold (" + std::to_string(frames) +
                          " frames of " + std::to_string(joints) + " joints need at least " +
                          std::to_string(transforms) + " bytes, " + std::to_string(remaining) +
                          " remain)");
    }
    m_doc.frame_time = frame_time;
    m_doc.num_frames = static_cast<int>(frames);
    m_doc.values.resize(count);
    if (channels > 0) parse_rows<true>(static_cast<int>(frames), static_cast<int>(channels));
    warn_extra_rows();
  }

  enum class RowProblem { MissingRow, ShortRow, NotANumber, NotFinite, LongRow };

  // Reports a problem at `p` in frame f (0-based), value c (0-based). Out of line and cold, so the
  // messages are not built in the hot loop.
  [[noreturn, gnu::cold, gnu::noinline]] void fail_in_rows(RowProblem problem, const char* p,
                                                           std::size_t line, const char* line_start,
                                                           int f, int c, int frames, int channels) {
    const char* data = m_cur.text().data();
    m_cur.reset(
        {static_cast<std::size_t>(p - data), line, static_cast<std::size_t>(line_start - data)});
    const std::string row = std::to_string(f + 1);
    switch (problem) {
      case RowProblem::MissingRow:
        fail_early(more(frames - f, "frame") + " (Frames: declares " + std::to_string(frames) +
                   ", the file holds " + std::to_string(f) + ")");
      case RowProblem::ShortRow:
        fail(std::to_string(channels) + " values on motion row " + row +
                 " (one per channel), not " + std::to_string(c),
             more(channels - c, "value") + " of frame " + row +
                 (f + 1 < frames ? ", then " + more(frames - f - 1, "frame") : ""));
      case RowProblem::NotANumber:
        fail("a number (value " + std::to_string(c + 1) + " of motion row " + row + ")");
      case RowProblem::NotFinite:
        fail("a finite number (value " + std::to_string(c + 1) + " of motion row " + row + ")");
      case RowProblem::LongRow:
        break;
    }
    fail("end of motion row " + row + " after its " + std::to_string(channels) + " values");
  }

  // The hot loop: plain pointers, one from_chars per value, line counting by hand. Without
  // kStore, the rows are only checked (each value read into one scratch double).
  template <bool kStore>
  void parse_rows(int frames, int channels) {
    const TextCursor::Mark start = m_cur.mark();
    const char* const data = m_cur.text().data();
    const char* const end = data + m_cur.text().size();
    const char* p = data + start.pos;
    const char* line_start = data + start.line_start;
    std::size_t line = start.line;
    double scratch = 0.0;
    double* out = kStore ? m_doc.values.data() : &scratch;
    for (int f = 0; f < frames; ++f) {
      for (;;) {  // skip blank lines
        while (p != end && is_blank(*p)) ++p;
        if (p == end) {
          fail_in_rows(RowProblem::MissingRow, p, line, line_start, f, 0, frames, channels);
        }
        if (*p != '\n' && *p != '\r') break;
        p += (*p == '\r' && p + 1 != end && p[1] == '\n') ? 2 : 1;
        ++line;
        line_start = p;
      }
      for (int c = 0; c < channels; ++c) {
        while (p != end && is_blank(*p)) ++p;
        if (p == end || *p == '\n' || *p == '\r') {
          fail_in_rows(RowProblem::ShortRow, p, line, line_start, f, c, frames, channels);
        }
        switch (parse_number(p, end, *out)) {
          case NumberStatus::Ok:
            break;
          case NumberStatus::NotANumber:
            fail_in_rows(RowProblem::NotANumber, p, line, line_start, f, c, frames, channels);
          case NumberStatus::NotFinite:
            fail_in_rows(RowProblem::NotFinite, p, line, line_start, f, c, frames, channels);
        }
        if constexpr (kStore) ++out;
      }
      while (p != end && is_blank(*p)) ++p;
      if (p != end && *p != '\n' && *p != '\r') {
        fail_in_rows(RowProblem::LongRow, p, line, line_start, f, channels, frames, channels);
      }
    }
    m_cur.reset(
        {static_cast<std::size_t>(p - data), line, static_cast<std::size_t>(line_start - data)});
  }

  // Rows beyond the declared count (a common exporter slip) are counted and dropped.
  void warn_extra_rows() {
    std::size_t extra = 0;
    std::size_t first_line = 0;
    m_cur.skip_inline_space();
    m_cur.consume_line_end();
    while (!m_cur.at_end()) {
      m_cur.skip_inline_space();
      if (!m_cur.at_line_end()) {
        if (extra++ == 0) first_line = m_cur.line();
      }
      m_cur.skip_line();
    }
    if (extra == 0) return;
    m_doc.warnings.push_back(m_cur.path() + ":" + std::to_string(first_line) +
                             ": warning: " + std::to_string(extra) + " extra motion row" +
                             (extra == 1 ? "" : "s") + " after the declared " +
                             std::to_string(m_doc.num_frames) + " frames ignored");
  }

  TextCursor m_cur;
  BvhDocument m_doc;
  std::vector<OpenJoint> m_open;  // joints whose block is open, innermost last
  std::unordered_map<std::string, std::size_t> m_name_lines;  // name → line it was defined on
  long long m_total_channels = 0;
};

// --- writing ---------------------------------------------------------------------------------

class BvhWriter {
 public:
  explicit BvhWriter(std::ostream& out) : m_out(out) { m_buf.reserve(kFlushAt + 4096); }

  void text(std::string_view s) {
    m_buf.append(s);
    if (m_buf.size() >= kFlushAt) flush();
  }
  void indent(int depth) { m_buf.append(static_cast<std::size_t>(depth), '\t'); }
  void number(double v) {
    char tmp[32];
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);  // shortest round-trip form
    m_buf.append(tmp, r.ptr);
  }
  void vector_line(int depth, const Eigen::Vector3d& v) {
    indent(depth);
    text("OFFSET ");
    number(v.x());
    text(" ");
    number(v.y());
    text(" ");
    number(v.z());
    text("\n");
  }
  void flush() {
    m_out.write(m_buf.data(), static_cast<std::streamsize>(m_buf.size()));
    m_buf.clear();
  }

 private:
  static constexpr std::size_t kFlushAt = 1 << 16;
  std::ostream& m_out;
  std::string m_buf;
};

bool writable_name(std::string_view name) {
  if (name.empty() || is_blank(name.front()) || is_blank(name.back())) return false;
  if (name.find_first_of("\r\n") != std::string_view::npos) return false;
  // read_name() would take a trailing " {" (or a lone "{") for the block's brace.
  if (name.back() == '{' && (name.size() == 1 || is_blank(name[name.size() - 2]))) return false;
  return true;
}

// Checks everything parse_bvh would reject; returns each joint's depth.
std::vector<int> check_writable(const BvhDocument& doc) {
  const Skeleton& skel = doc.skeleton;
  try {
    skel.validate();
  } catch (const Error& e) {
    throw ParameterError(std::string("write_bvh: ") + e.what());
  }
  if (!(doc.frame_time > 0.0) || !std::isfinite(doc.frame_time)) {
    throw ParameterError("write_bvh: frame time " + std::to_string(doc.frame_time) +
                         " is not a finite number > 0");
  }
  const auto expected = static_cast<std::size_t>(std::max(doc.num_frames, 0)) *
                        static_cast<std::size_t>(doc.num_channels());
  if (doc.num_frames < 0 || doc.values.size() != expected) {
    throw ParameterError("write_bvh: " + std::to_string(doc.values.size()) + " values for " +
                         std::to_string(doc.num_frames) + " frames of " +
                         std::to_string(doc.num_channels()) + " channels");
  }
  std::vector<int> depth(skel.joints.size(), 0);
  for (int j = 0; j < skel.num_joints(); ++j) {
    const Joint& joint = skel.joints[j];
    if (!writable_name(joint.name)) {
      throw ParameterError("write_bvh: joint " + std::to_string(j) + " has the name '" +
                           quote_token(joint.name) +
                           "', which BVH cannot hold (empty, leading/trailing blanks, a line end "
                           "or a trailing ' {')");
    }
    depth[j] = joint.parent < 0 ? 0 : depth[joint.parent] + 1;
    if (depth[j] >= kBvhMaxDepth) {
      throw ParameterError("write_bvh: joint '" + joint.name + "' is nested deeper than " +
                           std::to_string(kBvhMaxDepth) + " joints");
    }
    bool ok = joint.offset.allFinite();
    for (const auto& site : joint.end_sites) ok = ok && site.allFinite();
    if (!ok) throw ParameterError("write_bvh: joint '" + joint.name + "' has a non-finite offset");
  }
  for (std::size_t i = 0; i < doc.values.size(); ++i) {
    if (!std::isfinite(doc.values[i])) {
      throw ParameterError("write_bvh: value " + std::to_string(i) + " is not finite");
    }
  }
  return depth;
}

}  // namespace

BvhDocument parse_bvh(std::string_view text, const std::string& path) {
  // A UTF-8 byte order mark (some Windows tools write one) is not part of the text.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return BvhParser(text, path).parse();
}

BvhDocument read_bvh(const std::string& path) {
  return parse_bvh(read_text_file(path), path);
}

void write_bvh(const BvhDocument& doc, std::ostream& out) {
  const std::vector<int> depth = check_writable(doc);
  const Skeleton& skel = doc.skeleton;
  const int n = skel.num_joints();
  std::vector<std::vector<int>> children(n);
  std::vector<int> first_column(n, 0);
  for (int j = 0, column = 0; j < n; ++j) {
    if (skel.joints[j].parent >= 0) children[skel.joints[j].parent].push_back(j);
    first_column[j] = column;
    column += static_cast<int>(skel.joints[j].channels.size());
  }

  BvhWriter w(out);
  w.text("HIERARCHY\n");
  // Depth-first without recursion: a joint is pushed as ~j to close its block after its children.
  std::vector<int> stack;
  std::vector<int> columns;  // file column → document column
  for (auto it = skel.joints.rbegin(); it != skel.joints.rend(); ++it) {
    if (it->parent < 0) stack.push_back(static_cast<int>(skel.joints.rend() - it) - 1);
  }
  while (!stack.empty()) {
    const int item = stack.back();
    stack.pop_back();
    if (item < 0) {
      const int j = ~item;
      for (const auto& site : skel.joints[j].end_sites) {
        w.indent(depth[j] + 1);
        w.text("End Site\n");
        w.indent(depth[j] + 1);
        w.text("{\n");
        w.vector_line(depth[j] + 2, site);
        w.indent(depth[j] + 1);
        w.text("}\n");
      }
      w.indent(depth[j]);
      w.text("}\n");
      continue;
    }
    const Joint& joint = skel.joints[item];
    w.indent(depth[item]);
    w.text(joint.parent < 0 ? "ROOT " : "JOINT ");
    w.text(joint.name);
    w.text("\n");
    w.indent(depth[item]);
    w.text("{\n");
    w.vector_line(depth[item] + 1, joint.offset);
    // parse_bvh reads a leaf JOINT with `CHANNELS 0` as an End Site; a joint without channels,
    // children or End Sites is written without the line, which parse_bvh reads as a joint.
    const bool bare_leaf = joint.parent >= 0 && joint.channels.empty() && children[item].empty() &&
                           joint.end_sites.empty();
    if (!bare_leaf) {
      w.indent(depth[item] + 1);
      w.text("CHANNELS ");
      w.text(std::to_string(joint.channels.size()));
      for (const ChannelType c : joint.channels) {
        w.text(" ");
        w.text(channel_name(c));
      }
      w.text("\n");
    }
    for (std::size_t c = 0; c < joint.channels.size(); ++c) {
      columns.push_back(first_column[item] + static_cast<int>(c));
    }
    stack.push_back(~item);
    for (auto it = children[item].rbegin(); it != children[item].rend(); ++it) stack.push_back(*it);
  }

  w.text("MOTION\nFrames: ");
  w.text(std::to_string(doc.num_frames));
  w.text("\nFrame Time: ");
  w.number(doc.frame_time);
  w.text("\n");
  const std::size_t channels = columns.size();
  for (int f = 0; f < doc.num_frames; ++f) {
    const double* row = doc.values.data() + static_cast<std::size_t>(f) * channels;
    for (std::size_t c = 0; c < channels; ++c) {
      if (c > 0) w.text(" ");
      w.number(row[columns[c]]);
    }
    w.text("\n");
  }
  w.flush();
}

void write_bvh(const BvhDocument& doc, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path + ": error: cannot open for writing: " + std::strerror(errno));
  write_bvh(doc, out);
  out.flush();
  if (!out) throw Error(path + ": error: cannot write: " + std::strerror(errno));
}

Motion to_motion(const BvhDocument& doc) {
  const Skeleton& skel = doc.skeleton;
  const int joints = skel.num_joints();
  const auto channels = static_cast<std::size_t>(doc.num_channels());
  Motion motion;
  motion.frame_time = doc.frame_time;
  motion.resize(doc.num_frames, joints);
  std::vector<Axis> axes;
  std::vector<double> angles;
  for (int f = 0; f < doc.num_frames; ++f) {
    const double* value = doc.values.data() + static_cast<std::size_t>(f) * channels;
    for (int j = 0; j < joints; ++j) {
      const Joint& joint = skel.joints[j];
      Eigen::Vector3d translation = joint.offset;
      axes.clear();
      angles.clear();
      for (const ChannelType c : joint.channels) {
        const int axis = static_cast<int>(channel_axis(c));
        if (is_rotation(c)) {
          axes.push_back(static_cast<Axis>(axis));
          angles.push_back(deg_to_rad(*value));
        } else {
          translation[axis] = *value;
        }
        ++value;
      }
      motion.rotation(f, j) = euler_to_quat(axes, angles);
      motion.translation(f, j) = translation;
    }
  }
  return motion;
}

BvhDocument from_motion(const Skeleton& skeleton, const Motion& motion) {
  check_motion(skeleton, motion, "from_motion");
  const int joints = skeleton.num_joints();

  // Per joint: the channel carrying each distinct rotation axis (first occurrence, file order).
  struct Plan {
    std::array<Axis, 3> order{Axis::X, Axis::Y, Axis::Z};
    std::array<int, 3> column{-1, -1, -1};
    int axes = 0;
  };
  std::vector<Plan> plans(joints);
  for (int j = 0, column = 0; j < joints; ++j) {
    Plan& plan = plans[j];
    std::array<bool, 3> seen{false, false, false};
    for (const ChannelType c : skeleton.joints[j].channels) {
      const int axis = static_cast<int>(channel_axis(c));
      if (is_rotation(c) && !seen[axis]) {
        seen[axis] = true;
        plan.order[plan.axes] = static_cast<Axis>(axis);
        plan.column[plan.axes] = column;
        ++plan.axes;
      }
      ++column;
    }
    if (plan.axes == 2) {  // decompose in (i, j, k) with k the missing axis, then drop k
      for (int a = 0; a < 3; ++a) {
        if (!seen[a]) plan.order[2] = static_cast<Axis>(a);
      }
    }
  }

  BvhDocument doc;
  doc.skeleton = skeleton;
  doc.frame_time = motion.frame_time;
  doc.num_frames = motion.num_frames;
  const auto channels = static_cast<std::size_t>(skeleton.num_channels());
  doc.values.assign(static_cast<std::size_t>(motion.num_frames) * channels, 0.0);
  std::vector<Eigen::Vector3d> previous(joints, Eigen::Vector3d::Zero());
  for (int f = 0; f < motion.num_frames; ++f) {
    double* row = doc.values.data() + static_cast<std::size_t>(f) * channels;
    double* value = row;
    for (int j = 0; j < joints; ++j) {
      const Plan& plan = plans[j];
      const Eigen::Vector3d& t = motion.translation(f, j);
      for (const ChannelType c : skeleton.joints[j].channels) {
        if (!is_rotation(c)) *value = t[static_cast<int>(channel_axis(c))];
        ++value;
      }
      if (plan.axes == 0) continue;
      const Eigen::Quaterniond q = motion.rotation(f, j).normalized();
      Eigen::Vector3d angles = Eigen::Vector3d::Zero();
      if (plan.axes == 1) {
        // The twist about the axis: exact when q rotates about it only.
        const double s = q.vec()[static_cast<int>(plan.order[0])];
        const double a = 2.0 * std::atan2(q.w() < 0 ? -s : s, std::abs(q.w()));
        angles[0] = f == 0 ? a : wrap_near(a, previous[j][0]);
      } else {
        angles = quat_to_euler(q, plan.order, f == 0 ? nullptr : &previous[j]);
      }
      previous[j] = angles;
      for (int a = 0; a < plan.axes; ++a) row[plan.column[a]] = rad_to_deg(angles[a]);
    }
  }
  return doc;
}

Clip load_bvh(const std::string& path) {
  return load_bvh_text(read_text_file(path), path);
}

Clip load_bvh_text(std::string_view text, const std::string& path) {
  BvhDocument doc = parse_bvh(text, path);
  Clip clip;
  clip.path = path;
  clip.motion = to_motion(doc);
  clip.skeleton = std::move(doc.skeleton);
  clip.warnings = std::move(doc.warnings);
  return clip;
}

}  // namespace motionmap::io
