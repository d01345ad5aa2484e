// mesh.cpp — OBJ and PLY reading, OBJ writing. Every error names the file and
// the line (text) or the element (binary) that is wrong.
#include "mesh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace atmo::spheres {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

[[noreturn]] void fail_line(const std::string& path, size_t line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot + 1));
}

// Parses a whole token as a finite double; false if it is not one.
bool parse_double(const std::string& token, double& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && errno != ERANGE && std::isfinite(value);
}

bool parse_long(const std::string& token, long long& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(token.c_str(), &end, 10);
  return end == token.c_str() + token.size() && errno != ERANGE;
}

void check_finite(const std::string& path, const std::string& where, const glm::dvec3& v) {
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) fail(path, where + ": coordinate is not finite");
}

// ---------------------------------------------------------------- OBJ

TriangleMesh read_obj(const std::string& path, std::istream& in) {
  TriangleMesh mesh;
  struct PendingFace {
    glm::uvec3 tri;
    size_t line;
  };
  std::vector<PendingFace> faces;
  std::string line_text;
  size_t line = 0;
  while (std::getline(in, line_text)) {
    ++line;
    if (!line_text.empty() && line_text.back() == '\r') line_text.pop_back();
    std::istringstream ls(line_text);
    std::string keyword;
    if (!(ls >> keyword) || keyword[0] == '#') continue;
    if (keyword == "v") {
      std::string token;
      double xyz[3];
      for (int i = 0; i < 3; ++i) {
        if (!(ls >> token)) fail_line(path, line, "vertex needs x y z, got " + std::to_string(i) + " coordinate(s)");
        if (!parse_double(token, xyz[i])) fail_line(path, line, "vertex coordinate '" + token + "' is not a finite number");
      }
      mesh.vertices.push_back({xyz[0], xyz[1], xyz[2]});
    } else if (keyword == "f") {
      std::vector<long long> corners;
      std::string token;
      while (ls >> token) {
        // v, v/vt, v//vn, v/vt/vn: only the position index matters here.
        const std::string index_text = token.substr(0, token.find('/'));
        long long index = 0;
        if (!parse_long(index_text, index) || index == 0)
          fail_line(path, line, "face index '" + token + "' is not a non-zero integer");
        // Negative indices count back from the last vertex read so far.
        const long long resolved = index > 0 ? index - 1 : static_cast<long long>(mesh.vertices.size()) + index;
        if (resolved < 0) fail_line(path, line, "face index " + std::to_string(index) + " is before the first vertex");
        corners.push_back(resolved);
      }
      if (corners.size() < 3)
        fail_line(path, line, "face needs at least 3 vertices, got " + std::to_string(corners.size()));
      for (size_t i = 1; i + 1 < corners.size(); ++i)
        faces.push_back({glm::uvec3(static_cast<unsigned>(corners[0]), static_cast<unsigned>(corners[i]),
                                    static_cast<unsigned>(corners[i + 1])),
                         line});
    }
    // vt, vn, o, g, s, usemtl, mtllib, l, ...: not geometry we need.
  }
  if (in.bad()) fail(path, "read error");
  // Positive indices may name vertices defined later in the file, so they are checked at the end.
  for (const PendingFace& f : faces) {
    for (int k = 0; k < 3; ++k)
      if (f.tri[k] >= mesh.vertices.size())
        fail_line(path, f.line, "face index " + std::to_string(f.tri[k] + 1ull) + " is past the last vertex (" +
                                    std::to_string(mesh.vertices.size()) + " vertices)");
    mesh.triangles.push_back(f.tri);
  }
  return mesh;
}

// ---------------------------------------------------------------- PLY

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool ply_type(const std::string& name, PlyType& type) {
  static const struct {
    const char* name;
    PlyType type;
  } kTypes[] = {{"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
                {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
                {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
                {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
                {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
                {"float64", PlyType::Float64}};
  for (const auto& t : kTypes)
    if (name == t.name) {
      type = t.type;
      return true;
    }
  return false;
}

size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8: return 1;
    case PlyType::Int16:
    case PlyType::UInt16: return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  size_t header_line = 0;
  std::vector<PlyProperty> properties;
};

// Reads one binary little-endian value; false at the end of the data.
bool read_binary(std::istream& in, PlyType t, double& value) {
  unsigned char b[8];
  const size_t n = ply_size(t);
  if (!in.read(reinterpret_cast<char*>(b), static_cast<std::streamsize>(n))) return false;
  uint64_t u = 0;
  for (size_t i = 0; i < n; ++i) u |= static_cast<uint64_t>(b[i]) << (8 * i);
  switch (t) {
    case PlyType::Int8: value = static_cast<int8_t>(u); break;
    case PlyType::UInt8: value = static_cast<uint8_t>(u); break;
    case PlyType::Int16: value = static_cast<int16_t>(u); break;
    case PlyType::UInt16: value = static_cast<uint16_t>(u); break;
    case PlyType::Int32: value = static_cast<int32_t>(u); break;
    case PlyType::UInt32: value = static_cast<uint32_t>(u); break;
    case PlyType::Float32: {
      const uint32_t u32 = static_cast<uint32_t>(u);
      float f;
      std::memcpy(&f, &u32, 4);
      value = f;
      break;
    }
    case PlyType::Float64: std::memcpy(&value, &u, 8); break;
  }
  return true;
}

TriangleMesh read_ply(const std::string& path, std::istream& in) {
  std::string text;
  size_t line = 0;
  auto next_line = [&](std::string& out) -> bool {
    if (!std::getline(in, out)) return false;
    ++line;
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return true;
  };
  if (!next_line(text) || text != "ply") fail_line(path, 1, "not a PLY file (first line is not 'ply')");
  bool binary = false;
  bool have_format = false;
  std::vector<PlyElement> elements;
  for (;;) {
    if (!next_line(text)) fail(path, "PLY header has no end_header");
    std::istringstream ls(text);
    std::string keyword;
    if (!(ls >> keyword) || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      std::string format, version;
      ls >> format >> version;
      if (format == "ascii") binary = false;
      else if (format == "binary_little_endian") binary = true;
      else fail_line(path, line, "PLY format '" + format + "' is not supported (ascii or binary_little_endian)");
      have_format = true;
    } else if (keyword == "element") {
      PlyElement e;
      std::string count;
      if (!(ls >> e.name >> count) || !parse_long(count, e.count) || e.count < 0)
        fail_line(path, line, "element needs a name and a count >= 0");
      e.header_line = line;
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) fail_line(path, line, "property before any element");
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string count_type, item_type;
        ls >> count_type >> item_type >> p.name;
        p.is_list = true;
        if (!ply_type(count_type, p.count_type) || !ply_type(item_type, p.type))
          fail_line(path, line, "unknown PLY list types '" + count_type + " " + item_type + "'");
      } else {
        ls >> p.name;
        if (!ply_type(type, p.type)) fail_line(path, line, "unknown PLY type '" + type + "'");
      }
      if (p.name.empty()) fail_line(path, line, "property has no name");
      elements.back().properties.push_back(p);
    } else {
      fail_line(path, line, "unknown PLY header keyword '" + keyword + "'");
    }
  }
  if (!have_format) fail(path, "PLY header has no format line");

  TriangleMesh mesh;
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    int ix = -1, iy = -1, iz = -1, indices = -1;
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const PlyProperty& p = e.properties[i];
      const int k = static_cast<int>(i);
      if (is_vertex && !p.is_list && p.name == "x") ix = k;
      if (is_vertex && !p.is_list && p.name == "y") iy = k;
      if (is_vertex && !p.is_list && p.name == "z") iz = k;
      if (is_face && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) indices = k;
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0))
      fail_line(path, e.header_line, "element vertex has no x, y and z properties");
    if (is_face && indices < 0) fail_line(path, e.header_line, "element face has no vertex_indices list");

    for (long long item = 0; item < e.count; ++item) {
      const std::string where = "element " + e.name + " " + std::to_string(item);
      std::istringstream ls;
      if (!binary) {
        if (!next_line(text))
          fail(path, "file ends in " + where + " of " + std::to_string(e.count) + " (line " + std::to_string(line + 1) + ")");
        ls.str(text);
      }
      auto read_value = [&](PlyType t, double& v) -> bool {
        if (binary) return read_binary(in, t, v);
        std::string token;
        return static_cast<bool>(ls >> token) && parse_double(token, v);
      };
      auto bad = [&](const std::string& what) {
        if (binary) fail(path, where + " (binary): " + what);
        fail_line(path, line, where + ": " + what);
      };
      glm::dvec3 position(0.0);
      std::vector<long long> corners;
      for (size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        const int k = static_cast<int>(i);
        if (p.is_list) {
          double count = 0;
          if (!read_value(p.count_type, count))
            bad(binary ? "data ends early (truncated file)" : "missing list count of '" + p.name + "'");
          if (count < 0 || count != std::floor(count)) bad("list count of '" + p.name + "' is not a count");
          for (long long c = 0; c < static_cast<long long>(count); ++c) {
            double v = 0;
            if (!read_value(p.type, v))
              bad(binary ? "data ends early (truncated file)" : "missing item " + std::to_string(c) + " of '" + p.name + "'");
            if (k == indices) {
              if (v < 0 || v != std::floor(v)) bad("vertex index " + std::to_string(v) + " is not an index");
              corners.push_back(static_cast<long long>(v));
            }
          }
        } else {
          double v = 0;
          if (!read_value(p.type, v))
            bad(binary ? "data ends early (truncated file)" : "missing or malformed value of '" + p.name + "'");
          if (k == ix) position.x = v;
          if (k == iy) position.y = v;
          if (k == iz) position.z = v;
        }
      }
      if (is_vertex) {
        if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
          bad("coordinate is not finite");
        mesh.vertices.push_back(position);
      }
      if (is_face) {
        if (corners.size() < 3) bad("face needs at least 3 vertices, got " + std::to_string(corners.size()));
        for (long long c : corners)
          if (c >= static_cast<long long>(mesh.vertices.size()))
            bad("vertex index " + std::to_string(c) + " is past the last vertex (" +
                std::to_string(mesh.vertices.size()) + " vertices read before the faces)");
        for (size_t i = 1; i + 1 < corners.size(); ++i)
          mesh.triangles.push_back(glm::uvec3(static_cast<unsigned>(corners[0]), static_cast<unsigned>(corners[i]),
                                              static_cast<unsigned>(corners[i + 1])));
      }
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot open: ") + std::strerror(errno));
  const std::string ext = extension(path);
  char magic[4] = {0, 0, 0, 0};
  in.read(magic, 3);
  in.clear();
  in.seekg(0);
  const bool looks_ply = std::string(magic, 3) == "ply";
  TriangleMesh mesh;
  // The extension decides; an unknown one is read as PLY when it starts like one.
  if (ext == "ply" || (ext != "obj" && looks_ply)) mesh = read_ply(path, in);
  else mesh = read_obj(path, in);
  if (mesh.vertices.empty()) fail(path, "no vertices");
  if (mesh.triangles.empty()) fail(path, "no faces");
  for (size_t i = 0; i < mesh.vertices.size(); ++i) check_finite(path, "vertex " + std::to_string(i), mesh.vertices[i]);
  return mesh;
}

void write_obj(const TriangleMesh& mesh, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) fail(path, std::string("cannot write: ") + std::strerror(errno));
  std::fprintf(f, "# Atmo object mesh: metres, x forward, y left, z up; %zu vertices, %zu triangles\n",
               mesh.vertices.size(), mesh.triangles.size());
  // %.9g: micrometres at 1 km, and the same text for the same mesh on every machine.
  for (const glm::dvec3& v : mesh.vertices) std::fprintf(f, "v %.9g %.9g %.9g\n", v.x, v.y, v.z);
  for (const glm::uvec3& t : mesh.triangles) std::fprintf(f, "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) fail(path, "write error");
}

}  // namespace atmo::spheres
