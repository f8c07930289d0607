#include "core/io/mesh_io.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

// The comment that carries Material::double_sided through an .mtl file.
constexpr char kDoubleSidedTag[] = "# sylva double_sided";

// Appends " value" for each value: the shortest text that reads back as the
// same float (std::to_chars; at most 9 significant digits), several times
// faster than printf's %.9g on a mesh of 10^6 vertices.
void AppendFloats(const float* values, int count, std::string* text) {
  char buffer[32];
  for (int i = 0; i < count; ++i) {
    buffer[0] = ' ';
    const std::to_chars_result end = std::to_chars(buffer + 1, buffer + sizeof(buffer), values[i]);
    text->append(buffer, end.ptr);
  }
}

void AppendInt(int value, std::string* text) {
  char buffer[16];
  const std::to_chars_result end = std::to_chars(buffer, buffer + sizeof(buffer), value);
  text->append(buffer, end.ptr);
}

std::string FormatFloats(const char* keyword, const float* values, int count) {
  std::string line = keyword;
  AppendFloats(values, count, &line);
  return line + "\n";
}

std::string MtlText(const TriangleMesh& mesh) {
  std::string text = "# sylva materials\n";
  for (const Material& material : mesh.materials) {
    text += "\nnewmtl " + material.name + "\n";
    text += "Ka 0 0 0\n";
    text += FormatFloats("Kd", material.diffuse_color.data(), 3);
    text += "Ks 0 0 0\nillum 1\n";
    text += std::string(kDoubleSidedTag) + (material.double_sided ? " 1\n" : " 0\n");
  }
  return text;
}

std::string ObjText(const TriangleMesh& mesh, const std::string& mtl_name) {
  std::string out = "# sylva mesh: " + std::to_string(mesh.NumVertices()) + " vertices, " +
                    std::to_string(mesh.NumTriangles()) + " triangles\nmtllib " + mtl_name + "\n";
  // About 30 bytes per vertex and 20 per face.
  out.reserve(out.size() + 32 * mesh.vertices.size() + 24 * mesh.triangles.size());
  for (const Eigen::Vector3f& v : mesh.vertices) {
    out += 'v';
    AppendFloats(v.data(), 3, &out);
    out += '\n';
  }
  int current_material = -1;
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    if (mesh.triangle_materials[t] != current_material) {
      current_material = mesh.triangle_materials[t];
      out += "usemtl " + mesh.materials[current_material].name + "\n";
    }
    const Eigen::Vector3i& tri = mesh.triangles[t];
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      AppendInt(tri[k] + 1, &out);
    }
    out += '\n';
  }
  return out;
}

std::vector<std::string> SplitWords(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

// Reads lines, tracking "file:line" for error messages.
class LineReader {
 public:
  explicit LineReader(const fs::path& path) : path_(path.string()), in_(ReadFileToString(path)) {}
  bool Next(std::string* line) {
    if (!std::getline(in_, *line)) return false;
    ++line_number_;
    if (!line->empty() && line->back() == '\r') line->pop_back();
    return true;
  }
  std::string Where() const { return path_ + ":" + std::to_string(line_number_); }

 private:
  std::string path_;
  std::istringstream in_;
  int line_number_ = 0;
};

float ParseFloat(const std::string& word, const LineReader& reader) {
  char* end = nullptr;
  const double value = std::strtod(word.c_str(), &end);
  SYLVA_CHECK_INPUT(end != word.c_str() && *end == '\0' && std::isfinite(value), reader.Where())
      << "expected a finite number, got '" << word << "'";
  return static_cast<float>(value);
}

// An OBJ vertex reference ("7", "7/2", "7//3", "-1/..") as a 0-based index.
int ParseVertexRef(const std::string& word, int num_vertices, const LineReader& reader) {
  const std::string index_text = word.substr(0, word.find('/'));
  char* end = nullptr;
  const long value = std::strtol(index_text.c_str(), &end, 10);
  SYLVA_CHECK_INPUT(end != index_text.c_str() && *end == '\0' && value != 0, reader.Where())
      << "bad vertex index '" << word << "'";
  const long index = value > 0 ? value - 1 : num_vertices + value;
  SYLVA_CHECK_INPUT(index >= 0 && index < num_vertices, reader.Where())
      << "vertex index " << value << " out of range (" << num_vertices << " vertices so far)";
  return static_cast<int>(index);
}

void ParseMtl(const fs::path& path, TriangleMesh* mesh) {
  LineReader reader(path);
  int current = -1;
  for (std::string line; reader.Next(&line);) {
    if (line.rfind(kDoubleSidedTag, 0) == 0 && current >= 0) {
      const std::vector<std::string> words = SplitWords(line.substr(sizeof(kDoubleSidedTag) - 1));
      mesh->materials[current].double_sided = !words.empty() && words[0] == "1";
      continue;
    }
    const std::vector<std::string> words = SplitWords(line.substr(0, line.find('#')));
    if (words.empty()) continue;
    if (words[0] == "newmtl") {
      SYLVA_CHECK_INPUT(words.size() == 2, reader.Where()) << "expected 'newmtl NAME'";
      current = mesh->AddMaterial({words[1], Eigen::Vector3f(0.5f, 0.5f, 0.5f), false});
    } else if (words[0] == "Kd") {
      SYLVA_CHECK_INPUT(current >= 0, reader.Where()) << "'Kd' before any 'newmtl'";
      SYLVA_CHECK_INPUT(words.size() == 4, reader.Where()) << "expected 'Kd R G B'";
      for (int c = 0; c < 3; ++c) {
        mesh->materials[current].diffuse_color[c] = ParseFloat(words[c + 1], reader);
      }
    }
  }
}

int MaterialIndex(const std::string& name, TriangleMesh* mesh) {
  return mesh->AddMaterial({name, Eigen::Vector3f(0.5f, 0.5f, 0.5f), false});
}

void ParseFace(const std::vector<std::string>& words, int material, const LineReader& reader,
               TriangleMesh* mesh) {
  SYLVA_CHECK_INPUT(words.size() >= 4, reader.Where()) << "a face needs at least 3 vertices";
  std::vector<int> corners;
  for (size_t i = 1; i < words.size(); ++i) {
    corners.push_back(ParseVertexRef(words[i], mesh->NumVertices(), reader));
  }
  for (size_t i = 1; i + 1 < corners.size(); ++i) {
    mesh->AddTriangle(corners[0], corners[i], corners[i + 1], material);
  }
}

}  // namespace

void WriteObj(const fs::path& path, const TriangleMesh& mesh) {
  mesh.Check();
  const fs::path mtl_path = fs::path(path).replace_extension(".mtl");
  AtomicWriteString(mtl_path, MtlText(mesh));
  AtomicWriteString(path, ObjText(mesh, mtl_path.filename().string()));
}

TriangleMesh ReadObj(const fs::path& path) {
  LineReader reader(path);
  TriangleMesh mesh;
  int material = -1;
  for (std::string line; reader.Next(&line);) {
    const std::vector<std::string> words = SplitWords(line.substr(0, line.find('#')));
    if (words.empty()) continue;
    const std::string& keyword = words[0];
    if (keyword == "v") {
      SYLVA_CHECK_INPUT(words.size() == 4 || words.size() == 5, reader.Where())
          << "expected 'v X Y Z'";
      mesh.AddVertex(Eigen::Vector3f(ParseFloat(words[1], reader), ParseFloat(words[2], reader),
                                     ParseFloat(words[3], reader)));
    } else if (keyword == "f") {
      if (material < 0) material = MaterialIndex("default", &mesh);
      ParseFace(words, material, reader, &mesh);
    } else if (keyword == "usemtl") {
      SYLVA_CHECK_INPUT(words.size() == 2, reader.Where()) << "expected 'usemtl NAME'";
      material = MaterialIndex(words[1], &mesh);
    } else if (keyword == "mtllib") {
      SYLVA_CHECK_INPUT(words.size() == 2, reader.Where()) << "expected 'mtllib FILE'";
      ParseMtl(path.parent_path() / words[1], &mesh);
    }
  }
  return mesh;
}

}  // namespace sylva
