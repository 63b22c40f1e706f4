// prevalidate.cpp: the checks of prevalidate.h. Each walks the data the way OpenMesh 9's reader
// will (the same tokens, the same byte offsets) and refuses what would make that reader fail
// part way, where it goes on looping with stale values instead of stopping.
#include "prevalidate.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "failure.h"

namespace omsys {
namespace {

[[noreturn]] void bad(const std::string &what) { fail(OMSYS_READ_FAILED, what); }

bool is_space(uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/// Whitespace-separated tokens, as operator>> sees them.
class Tokens {
 public:
  Tokens(const uint8_t *d, std::size_t len, std::size_t pos) : d_(d), len_(len), pos_(pos) {}

  /// The next token, or an empty view at the end of the data.
  std::string_view next() {
    while (pos_ < len_ && is_space(d_[pos_])) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < len_ && !is_space(d_[pos_])) ++pos_;
    return std::string_view(reinterpret_cast<const char *>(d_) + start, pos_ - start);
  }
  /// Skips to just past the next newline, as std::getline; false if the data ends first.
  bool skip_line() {
    while (pos_ < len_ && d_[pos_] != '\n') ++pos_;
    if (pos_ == len_) return false;
    ++pos_;
    return true;
  }
  std::size_t remaining() const { return len_ - pos_; }

 private:
  const uint8_t *d_;
  std::size_t len_, pos_;
};

std::string quoted(std::string_view t) {
  std::string s(t.substr(0, 40));
  for (char &c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  }
  return "'" + s + (t.size() > 40 ? "...'" : "'");
}

/// A decimal integer that operator>> reads whole into a type with this range. Unsigned types
/// take no sign: libstdc++ would wrap "-1" around.
bool integer_token(std::string_view t, long long lo, unsigned long long hi) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty() || (t[0] == '-' && lo == 0)) return false;
  if (t[0] == '-') {
    long long v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    return r.ec == std::errc() && r.ptr == t.data() + t.size() && v >= lo;
  }
  unsigned long long v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && v <= hi;
}

bool unsigned_token(std::string_view t, uint64_t &value) {
  if (t.empty() || t[0] < '0' || t[0] > '9') return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), value);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && value <= std::numeric_limits<unsigned int>::max();
}

/// A face's vertex list as OpenMesh's ASCII readers take it (`>> n`, then n `>> index`): the
/// count no larger than the data could hold, each entry an unsigned index.
void check_index_list(Tokens &in, std::string_view first, const std::string &where) {
  uint64_t n = 0;
  if (!unsigned_token(first, n)) bad(where + "the vertex count " + quoted(first) + " is malformed");
  if (n > in.remaining() / 2 + 1) bad(where + "a vertex count larger than the data (" + std::to_string(n) + ")");
  for (uint64_t k = 0; k < n; ++k) {
    uint64_t idx = 0;
    const std::string_view v = in.next();
    if (v.empty()) bad(where + "the data ends early (truncated)");
    if (!unsigned_token(v, idx)) bad(where + "the vertex index " + quoted(v) + " is malformed");
  }
}

/// A decimal number that operator>> reads whole and finite into T (no inf, nan or hex).
template <class T>
bool float_token(std::string_view t) {
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) t.remove_prefix(1);
  if (t.empty() || t[0] == '+' || t[0] == '-') return false;
  for (char c : t) {
    if (!((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-')) return false;
  }
  T v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v, std::chars_format::general);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(v);
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class Type { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

/// The type names OpenMesh's PLY reader knows (get_property_type).
bool ply_type(std::string_view s, Type &t) {
  static const struct {
    const char *name;
    Type type;
  } kTypes[] = {{"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::Uint8},
                {"uint8", Type::Uint8},   {"short", Type::Int16},     {"int16", Type::Int16},
                {"ushort", Type::Uint16}, {"uint16", Type::Uint16},   {"int", Type::Int32},
                {"int32", Type::Int32},   {"uint", Type::Uint32},     {"uint32", Type::Uint32},
                {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64},
                {"float64", Type::Float64}};
  for (const auto &k : kTypes) {
    if (s == k.name) {
      t = k.type;
      return true;
    }
  }
  return false;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::Int8: case Type::Uint8: return 1;
    case Type::Int16: case Type::Uint16: return 2;
    case Type::Int32: case Type::Uint32: case Type::Float32: return 4;
    case Type::Float64: return 8;
  }
  return 0;
}

bool is_float(Type t) { return t == Type::Float32 || t == Type::Float64; }

/// How OpenMesh's ASCII reader extracts a property, which decides what a token must be.
enum class Read {
  Float,      // into a float: x, y, z, normals, texture coordinates, float colours
  Int,        // into an int: integer colours
  Character,  // into a char type: one character, not a number (custom char/uchar properties)
  Typed,      // into the declared type: other custom properties
  Token,      // into a string: properties of elements OpenMesh does not know
  Indices,    // the face's vertex list
};

struct Property {
  std::string name;
  Type type = Type::Float32;
  Type count_type = Type::Uint8;  // lists only
  Read read = Read::Float;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

bool ascii_value_ok(const Property &p, std::string_view t) {
  switch (p.read) {
    case Read::Float: return float_token<float>(t);
    case Read::Int: return integer_token(t, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
    case Read::Character: return t.size() == 1;
    case Read::Token: return !t.empty();
    case Read::Indices: return false;
    case Read::Typed: break;
  }
  switch (p.type) {
    case Type::Int16: return integer_token(t, -32768, 32767);
    case Type::Uint16: return integer_token(t, 0, 65535);
    case Type::Int32: return integer_token(t, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
    case Type::Uint32: return integer_token(t, 0, std::numeric_limits<unsigned int>::max());
    case Type::Float32: return float_token<float>(t);
    case Type::Float64: return float_token<double>(t);
    default: return t.size() == 1;
  }
}

struct PlyHeader {
  bool binary = false, big_endian = false;
  std::vector<Element> elements;
  std::size_t body = 0;  // where OpenMesh starts reading the data
};

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> w;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(static_cast<uint8_t>(line[i]))) ++i;
    const std::size_t s = i;
    while (i < line.size() && !is_space(static_cast<uint8_t>(line[i]))) ++i;
    if (i > s) w.push_back(line.substr(s, i - s));
  }
  return w;
}

/// The property as OpenMesh's header parser files it under its element.
Property ply_property(const Element &e, std::string_view name, Type type, int line) {
  const std::string where = "PLY header line " + std::to_string(line) + ": ";
  Property p;
  p.name = std::string(name);
  p.type = type;
  Type ignored;
  if (ply_type(name, ignored)) bad(where + "a property named like a type, " + quoted(name));
  const bool vertex = e.name == "vertex", face = e.name == "face";
  const bool coordinate = name == "x" || name == "y" || name == "z" || name == "nx" || name == "ny" ||
                          name == "nz" || name == "u" || name == "v" || name == "s" || name == "t";
  const bool colour = name == "red" || name == "green" || name == "blue" || name == "alpha" ||
                      (vertex && (name == "diffuse_red" || name == "diffuse_green" || name == "diffuse_blue"));
  if (vertex && coordinate) {
    // The binary reader converts only floating-point values to a float.
    if (!is_float(type)) bad(where + "the vertex property '" + p.name + "' must be float or double");
    p.read = Read::Float;
  } else if ((vertex || face) && colour) {
    // Integer colours are read as integers, float ones as floats; double ones as neither.
    if (type == Type::Float64) bad(where + "a double colour property ('" + p.name + "') is not supported");
    p.read = type == Type::Float32 ? Read::Float : Read::Int;
  } else if (vertex || face) {
    p.read = (type == Type::Int8 || type == Type::Uint8) ? Read::Character : Read::Typed;
  } else {
    p.read = Read::Token;
  }
  return p;
}

PlyHeader parse_ply_header(const uint8_t *d, std::size_t len) {
  PlyHeader h;
  std::size_t pos = 0, prev_terminator = 0;
  bool prev_comment = false, ended = false;
  int line_no = 0;
  bool seen_vertex = false, seen_face = false, seen_indices = false;
  while (pos < len && !ended) {
    const std::size_t start = pos;
    while (pos < len && d[pos] != '\n') ++pos;
    if (pos == len) break;  // a header line must end with a newline
    std::size_t end = pos;
    if (end > start && d[end - 1] == '\r') --end;
    const std::size_t terminator = end;
    ++pos;
    ++line_no;
    const std::string_view line(reinterpret_cast<const char *>(d) + start, end - start);
    const std::string where = "PLY header line " + std::to_string(line_no) + ": ";
    const auto w = words(line);
    if (line_no == 1) {
      if (w.size() != 1 || (w[0] != "ply" && w[0] != "PLY")) bad("not a PLY file (the first line is not 'ply')");
    } else if (line_no == 2) {
      if (w.size() != 3 || w[0] != "format" || w[2] != "1.0") {
        bad(where + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      }
      if (w[1] == "ascii") {
      } else if (w[1] == "binary_little_endian") {
        h.binary = true;
      } else if (w[1] == "binary_big_endian") {
        h.binary = h.big_endian = true;
      } else {
        bad(where + "unknown format " + quoted(w[1]));
      }
    } else if (!w.empty() && w[0] == "comment") {
      prev_comment = true;
      continue;
    } else if (w.size() == 1 && w[0] == "end_header") {
      ended = true;
      if (h.binary) {
        // OpenMesh seeks back to where the line before ended and skips "\nend_header\n" (12
        // bytes) or "\r\nend_header\r\n" (14); after a comment line it lands one line late.
        if (prev_comment) bad(where + "a comment line just before end_header in a binary PLY (OpenMesh misreads it)");
        const bool crlf = d[prev_terminator] == '\r';
        h.body = prev_terminator + (crlf ? 14 : 12);
        if (h.body != pos) bad(where + "the header mixes \\n and \\r\\n line ends (OpenMesh misplaces the data)");
      } else {
        h.body = pos;
      }
    } else if (w.size() == 3 && w[0] == "element") {
      Element e;
      e.name = std::string(w[1]);
      if (!unsigned_token(w[2], e.count)) bad(where + "the element count " + quoted(w[2]) + " is not a 32-bit count");
      if ((e.name == "vertex" && seen_vertex) || (e.name == "face" && seen_face)) {
        bad(where + "a second '" + e.name + "' element");
      }
      seen_vertex |= e.name == "vertex";
      seen_face |= e.name == "face";
      h.elements.push_back(std::move(e));
    } else if (w.size() == 3 && w[0] == "property") {
      if (h.elements.empty()) bad(where + "a property before any element");
      Type t;
      if (!ply_type(w[1], t)) bad(where + "unknown property type " + quoted(w[1]));
      Element &e = h.elements.back();
      e.properties.push_back(ply_property(e, w[2], t, line_no));
    } else if (w.size() == 5 && w[0] == "property" && w[1] == "list") {
      if (h.elements.empty()) bad(where + "a property before any element");
      Element &e = h.elements.back();
      if (e.name != "face" || (w[4] != "vertex_indices" && w[4] != "vertex_index")) {
        bad(where + "the only list property supported is the face's vertex_indices");
      }
      if (seen_indices) bad(where + "a second vertex_indices property");
      seen_indices = true;
      Property p;
      p.name = std::string(w[4]);
      p.read = Read::Indices;
      // OpenMesh reads list counts of these types only.
      if (w[2] == "uchar" || w[2] == "uint8") {
        p.count_type = Type::Uint8;
      } else if (w[2] == "uint16") {
        p.count_type = Type::Uint16;
      } else if (w[2] == "int") {
        p.count_type = Type::Int32;
      } else {
        bad(where + "unsupported list count type " + quoted(w[2]) + " (uchar, uint8, uint16 or int)");
      }
      if (!ply_type(w[3], p.type) || is_float(p.type)) bad(where + "the vertex indices must have an integer type");
      e.properties.push_back(std::move(p));
    } else {
      bad(where + "not a PLY header line OpenMesh reads as written: " + quoted(line));
    }
    prev_comment = false;
    prev_terminator = terminator;
  }
  if (!ended) bad("the PLY header has no end_header line");
  int coordinates = 0;
  for (const Element &e : h.elements) {
    if (e.count > 0 && e.properties.empty()) bad("the PLY element '" + e.name + "' has records but no properties");
    if (e.name != "vertex") continue;
    for (const char *c : {"x", "y", "z"}) {
      int n = 0;
      for (const Property &p : e.properties) n += p.name == c;
      if (n != 1) bad(std::string("the PLY vertex element needs exactly one property '") + c + "'");
      ++coordinates;
    }
  }
  if (coordinates != 3) bad("the PLY file has no vertex element");
  if (seen_face && !seen_indices) bad("the PLY face element has no vertex_indices list");
  return h;
}

void check_ply_ascii(const PlyHeader &h, const uint8_t *d, std::size_t len) {
  Tokens in(d, len, h.body);
  for (const Element &e : h.elements) {
    for (uint64_t i = 0; i < e.count; ++i) {
      const auto where = [&] { return "PLY " + e.name + " " + std::to_string(i) + ": "; };
      for (const Property &p : e.properties) {
        const std::string_view t = in.next();
        if (t.empty()) bad(where() + "the data ends early (truncated)");
        if (p.read != Read::Indices) {
          if (!ascii_value_ok(p, t)) bad(where() + "the " + p.name + " value " + quoted(t) + " is malformed");
          continue;
        }
        check_index_list(in, t, where());
      }
    }
    if (e.name == "face") return;  // OpenMesh stops after the faces
  }
}

uint64_t read_uint(const uint8_t *p, std::size_t n, bool big_endian) {
  uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<uint64_t>(p[big_endian ? n - 1 - i : i]) << (8 * i);
  return v;
}

void check_ply_binary(const PlyHeader &h, const uint8_t *d, std::size_t len) {
  std::size_t pos = h.body;
  for (const Element &e : h.elements) {
    // Records of fixed size: checked at once, so that a huge count costs nothing.
    bool fixed = true;
    std::size_t record = 0;
    for (const Property &p : e.properties) {
      fixed &= p.read != Read::Indices;
      record += type_size(p.type);
    }
    if (fixed) {
      if (record != 0 && e.count > (len - pos) / record) bad("PLY " + e.name + ": the data ends early (truncated)");
      pos += static_cast<std::size_t>(e.count) * record;
    } else {
      for (uint64_t i = 0; i < e.count; ++i) {
        const auto where = [&] { return "PLY " + e.name + " " + std::to_string(i) + ": "; };
        for (const Property &p : e.properties) {
          if (p.read != Read::Indices) {
            if (len - pos < type_size(p.type)) bad(where() + "the data ends early (truncated)");
            pos += type_size(p.type);
            continue;
          }
          const std::size_t cs = type_size(p.count_type);
          if (len - pos < cs) bad(where() + "the data ends early (truncated)");
          uint64_t n = read_uint(d + pos, cs, h.big_endian);
          pos += cs;
          if (p.count_type == Type::Int32 && n > 0x7fffffffu) bad(where() + "a negative vertex count");
          if (n > (len - pos) / type_size(p.type)) bad(where() + "the data ends early (truncated)");
          pos += static_cast<std::size_t>(n) * type_size(p.type);
        }
      }
    }
    if (e.name == "face") return;
  }
}

}  // namespace

void check_ply(const uint8_t *data, std::size_t len) {
  const PlyHeader h = parse_ply_header(data, len);
  if (h.binary) {
    check_ply_binary(h, data, len);
  } else {
    check_ply_ascii(h, data, len);
  }
}

// ---------------------------------------------------------------------------------------------
// OFF

void check_off(const uint8_t *d, std::size_t len) {
  // OpenMesh reads the first line as the header, whatever it says, and from a stream it never
  // looks at it: a COFF, NOFF or OFF BINARY file would be read as plain OFF.
  std::size_t eol = 0;
  while (eol < len && d[eol] != '\n') ++eol;
  const auto head = words(std::string_view(reinterpret_cast<const char *>(d), eol));
  if (head.size() != 1 || head[0] != "OFF") {
    bad("OFF through OpenMesh: the first line must be 'OFF' alone (no COFF, NOFF, STOFF, BINARY or counts)");
  }
  if (eol == len) bad("the OFF data ends after its header (truncated)");
  Tokens in(d, len, eol + 1);
  uint64_t counts[3];
  for (uint64_t &c : counts) {
    const std::string_view t = in.next();
    if (!unsigned_token(t, c)) bad("the OFF counts (vertices faces edges) are missing or malformed");
  }
  const uint64_t nv = counts[0], nf = counts[1];
  for (uint64_t i = 0; i < nv; ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::string_view t = in.next();
      if (t.empty()) bad("OFF vertex " + std::to_string(i) + ": the data ends early (truncated)");
      if (!float_token<float>(t)) bad("OFF vertex " + std::to_string(i) + ": the coordinate " + quoted(t) + " is malformed");
    }
    // The rest of the line is skipped; at the end of the data OpenMesh stops reading.
    if (!in.skip_line() && (i + 1 < nv || nf > 0)) bad("OFF vertex " + std::to_string(i) + ": the data ends early (truncated)");
  }
  for (uint64_t i = 0; i < nf; ++i) {
    const std::string where = "OFF face " + std::to_string(i) + ": ";
    const std::string_view t = in.next();
    if (t.empty()) bad(where + "the data ends early (truncated)");
    check_index_list(in, t, where);
  }
}

// ---------------------------------------------------------------------------------------------
// OM

namespace {

uint32_t read_le32(const uint8_t *p) { return static_cast<uint32_t>(read_uint(p, 4, false)); }

}  // namespace

/// OpenMesh's OM reader trusts every size in the file and asserts on chunk headers it does not
/// expect (Debian builds it with assertions: a corrupt file would abort the process). So the
/// chunks are walked first, and only the layout OpenMesh 7 to 9 writes (OM 2.0 to 2.2) is
/// passed on: known chunk kinds with the dimensions OpenMesh asserts, each inside the data, and
/// each entity's chunks after the chunk that creates its elements (then every element count
/// the reader checks against is the header's).
void check_om(const uint8_t *d, std::size_t len) {
  // OpenMesh's OM reader accepts a file without a header as an empty mesh.
  if (!(len >= 16 && d[0] == 'O' && d[1] == 'M')) bad("not an OM file (no OM header)");
  const unsigned major = d[3] >> 5, minor = d[3] & 0x1f;
  if (major != 2 || minor > 2) {
    bad("OM version " + std::to_string(major) + "." + std::to_string(minor) +
        " is not supported (OM 2.0 to 2.2, written by OpenMesh 7 to 9)");
  }
  const uint64_t nv = read_le32(d + 4), nf = read_le32(d + 8), ne = read_le32(d + 12);
  std::size_t pos = 16, chunk = 16;
  const auto corrupt = [&](const std::string &what) {
    bad("corrupt OM file: " + what + " (chunk at byte " + std::to_string(chunk) + ")");
  };
  const auto need = [&](uint64_t n) {
    if (n > len - pos) corrupt("the data ends inside the chunk");
  };
  bool have_v = false, have_h = false, have_f = false;
  for (;;) {
    chunk = pos;
    need(2);
    const unsigned h = d[pos] | d[pos + 1] << 8;
    pos += 2;
    const unsigned named = (h >> 1) & 1, entity = (h >> 2) & 7, type = (h >> 5) & 15, is_float = (h >> 10) & 1,
                   dim = (h >> 11) & 7, bits = (h >> 14) & 3;
    if (entity == 7) return;  // the end-of-chunks marker
    if (named) {
      need(1);
      const std::size_t n = d[pos];
      need(1 + n);
      pos += 1 + n;
    }
    uint64_t count;
    bool created;  // the chunk that creates the entity's elements came before
    switch (entity) {
      case 0: count = nv, created = have_v; break;
      case 1: count = 1, created = true; break;
      case 2: count = nf, created = have_f; break;
      case 4: count = ne, created = have_h; break;
      case 6: count = 2 * ne, created = have_h; break;
      default: corrupt("unknown entity " + std::to_string(entity));
    }
    const uint64_t int_size = uint64_t(1) << bits;
    uint64_t size = 0;
    switch (type) {
      case 6: {  // custom property: [type name,] block size, block
        if (!created) corrupt("a property before its elements");
        if (minor >= 2) {
          need(1);
          const std::size_t n = d[pos];
          need(1 + n);
          pos += 1 + n;
        }
        need(4);
        size = read_le32(d + pos);
        pos += 4;
        break;
      }
      case 7:  // topology
        if (entity == 0 && have_v) {
          size = nv * int_size;
        } else if (entity == 6 && have_v && !have_h) {
          size = ne * 6 * int_size;
          have_h = true;
        } else if (entity == 2 && have_h && !have_f) {
          size = nf * int_size;
          have_f = true;
        } else {
          corrupt("an unexpected topology chunk");
        }
        break;
      case 0:  // positions
        if (entity != 0 || have_v || dim != 2 || bits > 1) corrupt("an unexpected position chunk");
        size = nv * 3 * (bits == 0 ? 4 : 8);
        have_v = true;
        break;
      case 1:  // normals
        if ((entity != 0 && entity != 2) || !created || dim != 2 || bits > 1) corrupt("an unexpected normal chunk");
        size = count * 3 * (bits == 0 ? 4 : 8);
        break;
      case 2:  // texture coordinates: read as 2 floats
        if (entity != 0 || !created || dim != 1 || bits != 0 || !is_float) corrupt("an unexpected texcoord chunk");
        size = nv * 8;
        break;
      case 3:  // status: read as one unsigned int per element, whatever the header says
        if (entity == 1 || !created || dim != 0) corrupt("an unexpected status chunk");
        size = count * sizeof(unsigned int);
        break;
      case 4:  // colors: read as 3 bytes
        if ((entity != 0 && entity != 2) || !created || dim != 2 || bits != 0 || is_float) {
          corrupt("an unexpected color chunk");
        }
        size = count * 3;
        break;
      default:
        corrupt("an unknown chunk type " + std::to_string(type));
    }
    need(size);
    pos += size;
  }
}

}  // namespace omsys
