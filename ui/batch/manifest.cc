#include "ui/batch/manifest.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "ui/batch/csv.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {
namespace {

// The columns that are not options, in the order a written manifest has them.
const char* const kColumns[] = {"name",          "photos", "colmap",   "cameras", "register",
                                "loose_cameras", "mattes", "held_out", "units"};
const char kLogsFolder[] = "logs";

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r") - begin + 1);
}

bool IsColumn(const std::string& name) {
  return std::find(std::begin(kColumns), std::end(kColumns), name) != std::end(kColumns);
}

// Where each column is, from the header row; option columns are checked
// against the option registry.
struct Header {
  std::map<std::string, size_t> columns;                    // name -> field index
  std::vector<std::pair<std::string, size_t>> option_keys;  // Section.field -> index
};

Header ReadHeader(const CsvRecord& record, const std::string& source) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  Header header;
  std::set<std::string> seen;
  const std::string where = source + ":" + std::to_string(record.line);
  for (size_t i = 0; i < record.fields.size(); ++i) {
    std::string name = Trim(record.fields[i]);
    SYLVA_CHECK_INPUT(!name.empty(), where) << "column " << i + 1 << " of the header has no name";
    SYLVA_CHECK_INPUT(seen.insert(name).second, where) << "column '" << name << "' appears twice";
    if (name.find('.') != std::string::npos) {
      SYLVA_CHECK_INPUT(registry.Has(name), where)
          << "unknown option column '" << name << "' (see 'sylva help options')";
      header.option_keys.emplace_back(name, i);
      continue;
    }
    std::replace(name.begin(), name.end(), '-', '_');
    SYLVA_CHECK_INPUT(IsColumn(name), where)
        << "unknown column '" << record.fields[i]
        << "' (columns: name, photos, colmap, cameras, register, loose_cameras, mattes, "
           "held_out, units, and options as Section.field)";
    header.columns[name] = i;
  }
  SYLVA_CHECK_INPUT(header.columns.count("name") > 0, where)
      << "the header has no 'name' column (the first row names the columns)";
  SYLVA_CHECK_INPUT(header.columns.count("photos") > 0, where)
      << "the header has no 'photos' column";
  return header;
}

bool IsNameCharacter(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ||
         c == '+';
}

// The non-empty names of `text` separated by `separator`, trimmed.
std::vector<std::string> SplitNames(const std::string& text, char separator) {
  std::vector<std::string> names;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(separator, begin);
    if (end == std::string::npos) end = text.size();
    const std::string name = Trim(text.substr(begin, end - begin));
    if (!name.empty()) names.push_back(name);
    begin = end + 1;
  }
  return names;
}

void CheckName(const std::string& name, const std::string& where) {
  SYLVA_CHECK_INPUT(!name.empty(), where) << "the tree has no name";
  for (char c : name) {
    SYLVA_CHECK_INPUT(IsNameCharacter(c), where)
        << "name '" << name << "': use letters, digits, '.', '_', '-' and '+' only";
  }
  SYLVA_CHECK_INPUT(name[0] != '.', where) << "name '" << name << "' must not start with '.'";
  SYLVA_CHECK_INPUT(name != kLogsFolder, where) << "name 'logs' is taken by the batch's log folder";
}

// Reads one data row into a tree.
class RowReader {
 public:
  RowReader(const Header& header, const CsvRecord& record, const fs::path& base,
            const std::string& source)
      : header_(header),
        record_(record),
        base_(base),
        where_(source + ":" + std::to_string(record.line)) {}

  ManifestTree Read() const {
    SYLVA_CHECK_INPUT(record_.fields.size() <= NumColumns(), where_)
        << record_.fields.size() << " fields, but the header names " << NumColumns() << " columns";
    ManifestTree tree;
    tree.line = record_.line;
    tree.name = Cell("name");
    CheckName(tree.name, where_);
    tree.photos_dir = Path("photos", Kind::kFolder);
    SYLVA_CHECK_INPUT(!tree.photos_dir.empty(), where_) << "'photos' is empty (a folder is needed)";
    tree.colmap_model_dir = Path("colmap", Kind::kFolder);
    tree.camera_file = Path("cameras", Kind::kFile);
    tree.register_method = Cell("register");
    tree.loose_cameras_file = Path("loose_cameras", Kind::kFile);
    tree.mattes_dir = Path("mattes", Kind::kFolder);
    tree.held_out = HeldOut();
    tree.units = Cell("units");
    CheckCameraSource(tree);
    for (const auto& [key, index] : header_.option_keys) {
      const std::string value = index < record_.fields.size() ? Trim(record_.fields[index]) : "";
      if (!value.empty()) tree.options.emplace_back(key, value);
    }
    return tree;
  }

 private:
  enum class Kind { kFile, kFolder };

  size_t NumColumns() const { return header_.columns.size() + header_.option_keys.size(); }

  std::string Cell(const std::string& column) const {
    const auto it = header_.columns.find(column);
    if (it == header_.columns.end() || it->second >= record_.fields.size()) return "";
    return Trim(record_.fields[it->second]);
  }

  fs::path Resolve(const std::string& text) const {
    return (base_ / fs::path(text)).lexically_normal();
  }

  fs::path Path(const std::string& column, Kind kind) const {
    const std::string text = Cell(column);
    if (text.empty()) return {};
    const fs::path path = Resolve(text);
    std::error_code ec;
    const bool ok =
        kind == Kind::kFolder ? fs::is_directory(path, ec) : fs::is_regular_file(path, ec);
    SYLVA_CHECK_INPUT(ok, where_) << "'" << column
                                  << "': " << (kind == Kind::kFolder ? "folder" : "file")
                                  << " not found: " << path.string();
    return path;
  }

  std::vector<std::string> HeldOut() const {
    std::string text = Cell("held_out");
    char separator = ';';
    if (!text.empty() && text[0] == '@') {
      const fs::path file = Resolve(Trim(text.substr(1)));
      std::error_code ec;
      SYLVA_CHECK_INPUT(fs::is_regular_file(file, ec), where_)
          << "'held_out': file not found: " << file.string();
      text = ReadFileToString(file);
      separator = '\n';
    } else {
      std::replace(text.begin(), text.end(), ',', ';');
    }
    return SplitNames(text, separator);
  }

  void CheckCameraSource(const ManifestTree& tree) const {
    const int sources =
        !tree.colmap_model_dir.empty() + !tree.camera_file.empty() + !tree.register_method.empty();
    SYLVA_CHECK_INPUT(sources == 1, where_)
        << (sources == 0 ? "no camera source" : "more than one camera source")
        << ": give exactly one of 'colmap', 'cameras' and 'register'";
    SYLVA_CHECK_INPUT(tree.register_method.empty() || tree.register_method == "colmap" ||
                          tree.register_method == "manual",
                      where_)
        << "'register': expected colmap or manual, got '" << tree.register_method << "'";
    const bool manual = tree.register_method == "manual";
    SYLVA_CHECK_INPUT(manual == !tree.loose_cameras_file.empty(), where_)
        << (manual ? "'register' manual needs 'loose_cameras' (a loose-camera file)"
                   : "'loose_cameras' is only used with 'register' manual");
  }

  const Header& header_;
  const CsvRecord& record_;
  fs::path base_;
  std::string where_;
};

bool IsImageFile(const fs::path& path) {
  static const std::set<std::string> kExtensions = {".jpg",  ".jpeg", ".png", ".tif",
                                                    ".tiff", ".exr",  ".bmp"};
  return kExtensions.count(Lower(path.extension().string())) > 0;
}

bool HasImages(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  for (const auto& entry : fs::recursive_directory_iterator(dir, ec)) {
    if (entry.is_regular_file(ec) && IsImageFile(entry.path())) return true;
  }
  return false;
}

bool IsColmapModel(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "cameras.txt", ec) ||
         fs::is_regular_file(dir / "cameras.bin", ec);
}

// The first of `names` under `dir` that `accept` takes; empty if none.
template <typename Accept>
fs::path FirstOf(const fs::path& dir, std::initializer_list<const char*> names, Accept accept) {
  for (const char* name : names) {
    if (accept(dir / name)) return dir / name;
  }
  return {};
}

// A tree folder as a manifest row; false if it holds no photos.
bool ScanTreeFolder(const fs::path& folder, ManifestTree* tree) {
  std::error_code ec;
  const auto is_file = [&](const fs::path& p) { return fs::is_regular_file(p, ec); };
  tree->name = folder.filename().string();
  for (char& c : tree->name) {
    if (!IsNameCharacter(c)) c = '_';
  }
  tree->photos_dir = FirstOf(folder, {"photos", "images"}, HasImages);
  if (tree->photos_dir.empty()) {
    bool direct = false;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      direct = direct || (entry.is_regular_file(ec) && IsImageFile(entry.path()));
    }
    if (!direct) return false;
    tree->photos_dir = folder;
  }
  tree->camera_file = FirstOf(folder, {"cameras.json"}, is_file);
  if (tree->camera_file.empty()) {
    tree->colmap_model_dir = FirstOf(folder, {"colmap", "sparse/0", "sparse"}, IsColmapModel);
  }
  if (tree->camera_file.empty() && tree->colmap_model_dir.empty()) {
    tree->loose_cameras_file =
        FirstOf(folder, {"loose_cameras.json", "loose-cameras.json"}, is_file);
    tree->register_method = tree->loose_cameras_file.empty() ? "colmap" : "manual";
  }
  tree->mattes_dir = FirstOf(folder, {"mattes"}, HasImages);
  const fs::path held_out = FirstOf(folder, {"held_out.txt", "held-out.txt"}, is_file);
  if (!held_out.empty()) tree->held_out = SplitNames(ReadFileToString(held_out), '\n');
  return true;
}

std::string RelativeText(const fs::path& path, const fs::path& base) {
  if (path.empty()) return "";
  const fs::path relative = path.lexically_relative(base);
  return relative.empty() ? path.string() : relative.generic_string();
}

}  // namespace

ProjectSetup ManifestTree::Setup(const fs::path& out_dir) const {
  ProjectSetup setup;
  setup.root = out_dir / name;
  setup.photos_dir = photos_dir;
  setup.colmap_model_dir = colmap_model_dir;
  setup.camera_file = camera_file;
  setup.register_method = register_method;
  setup.loose_cameras_file = loose_cameras_file;
  setup.mattes_dir = mattes_dir;
  setup.held_out = held_out;
  setup.units = units;
  return setup;
}

std::string ManifestTree::InputsKey() const {
  std::string text = photos_dir.string() + ";" + colmap_model_dir.string() + ";" +
                     camera_file.string() + ";" + register_method + ";" +
                     loose_cameras_file.string() + ";" + mattes_dir.string() + ";" + units + ";";
  for (const std::string& view : held_out) text += view + ",";
  return HexString(Fnv1a64(text));
}

const ManifestTree* Manifest::Find(const std::string& name) const {
  for (const ManifestTree& tree : trees) {
    if (tree.name == name) return &tree;
  }
  return nullptr;
}

Manifest ParseManifest(const std::string& text, const fs::path& path) {
  const std::string source = path.string();
  const std::vector<CsvRecord> records = ParseCsv(text, source);
  SYLVA_CHECK_INPUT(!records.empty(), source)
      << "empty manifest (expected a header row: name,photos,...)";
  const Header header = ReadHeader(records[0], source);
  Manifest manifest;
  manifest.path = fs::absolute(path).lexically_normal();
  std::map<std::string, const ManifestTree*> trees_by_name;  // lower-case name -> tree
  manifest.trees.reserve(records.size());
  for (size_t r = 1; r < records.size(); ++r) {
    ManifestTree tree = RowReader(header, records[r], manifest.path.parent_path(), source).Read();
    const auto it = trees_by_name.find(Lower(tree.name));
    SYLVA_CHECK_INPUT(it == trees_by_name.end(), source + ":" + std::to_string(tree.line))
        << "duplicate name '" << tree.name << "' (line " << it->second->line << " has '"
        << it->second->name << "'; project folders must differ, also ignoring case)";
    manifest.trees.push_back(std::move(tree));
    trees_by_name[Lower(manifest.trees.back().name)] = &manifest.trees.back();
  }
  SYLVA_CHECK_INPUT(!manifest.trees.empty(), source) << "no trees (only a header row)";
  return manifest;
}

Manifest ReadManifest(const fs::path& path) { return ParseManifest(ReadFileToString(path), path); }

std::vector<ManifestTree> ScanTreeFolders(const fs::path& dir) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_directory(dir, ec), dir.string()) << "folder not found";
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory(ec) && !name.empty() && name[0] != '.') folders.push_back(entry.path());
  }
  std::sort(folders.begin(), folders.end());
  std::vector<ManifestTree> trees;
  for (const fs::path& folder : folders) {
    ManifestTree tree;
    if (ScanTreeFolder(fs::absolute(folder).lexically_normal(), &tree)) {
      trees.push_back(std::move(tree));
    }
  }
  SYLVA_CHECK_INPUT(!trees.empty(), dir.string())
      << "no tree folders (sub-folders with photos, in photos/, images/ or the folder itself)";
  return trees;
}

std::string ManifestText(const std::vector<ManifestTree>& trees, const fs::path& manifest_dir) {
  const fs::path base = fs::absolute(manifest_dir).lexically_normal();
  std::string text = CsvLine(std::vector<std::string>(std::begin(kColumns), std::end(kColumns)));
  for (const ManifestTree& tree : trees) {
    std::string held_out;
    for (const std::string& name : tree.held_out) held_out += (held_out.empty() ? "" : ";") + name;
    text +=
        CsvLine({tree.name, RelativeText(tree.photos_dir, base),
                 RelativeText(tree.colmap_model_dir, base), RelativeText(tree.camera_file, base),
                 tree.register_method, RelativeText(tree.loose_cameras_file, base),
                 RelativeText(tree.mattes_dir, base), held_out, tree.units});
  }
  return text;
}

}  // namespace sylva
