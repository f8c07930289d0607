#include "core/io/qsm_io.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"

namespace sylva {
namespace {

// An axis read from a file may be this far from unit length (TreeQSM keeps
// float32 values, |axis| = 1 +- 1e-7) and is normalised; further is an error.
constexpr double kAxisReadTolerance = 1e-3;
constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";
// A checked model's axes are unit within this.
constexpr double kAxisCheckTolerance = 1e-9;
// A child starting this close (relative) to its parent's end shares its node.
constexpr double kCoincidenceTolerance = 1e-9;
// A child attaching closer than this fraction of its parent's length to the
// parent's end attaches at the end node; closer to its start, at this fraction.
constexpr double kSplitSnap = 0.05;

const char* const kColumns[] = {"id",      "parent_id", "start_x", "start_y",
                                "start_z", "axis_x",    "axis_y",  "axis_z",
                                "length",  "radius",    "branch",  "branch_order"};

// Index of each cylinder id; Error (or nothing) on duplicates is the caller's business.
std::unordered_map<int64_t, int> IndexById(const std::vector<QsmCylinder>& cylinders) {
  std::unordered_map<int64_t, int> index;
  for (int i = 0; i < static_cast<int>(cylinders.size()); ++i) index.emplace(cylinders[i].id, i);
  return index;
}

// Returns the index of a cylinder on a parent cycle, or -1 if every cylinder
// reaches a root. Assumes ids unique and parents present.
int FindCycle(const std::vector<QsmCylinder>& cylinders) {
  const std::unordered_map<int64_t, int> index = IndexById(cylinders);
  // 0 = unvisited, 1 = on the current walk, 2 = reaches a root.
  std::vector<char> state(cylinders.size(), 0);
  for (int i = 0; i < static_cast<int>(cylinders.size()); ++i) {
    std::vector<int> walk;
    int j = i;
    while (j >= 0 && state[j] == 0) {
      state[j] = 1;
      walk.push_back(j);
      j = cylinders[j].parent_id == 0 ? -1 : index.at(cylinders[j].parent_id);
    }
    if (j >= 0 && state[j] == 1) return j;
    for (int k : walk) state[k] = 2;
  }
  return -1;
}

}  // namespace

void QsmModel::Check() const {
  const std::unordered_map<int64_t, int> index = IndexById(cylinders);
  SYLVA_CHECK(index.size() == cylinders.size()) << "QSM cylinder ids are not unique";
  for (const QsmCylinder& c : cylinders) {
    SYLVA_CHECK(c.id > 0) << "QSM cylinder id " << c.id << " is not > 0";
    SYLVA_CHECK(c.parent_id == 0 || index.count(c.parent_id) > 0)
        << "QSM cylinder " << c.id << " has a missing parent " << c.parent_id;
    SYLVA_CHECK(c.start.allFinite() && c.axis.allFinite()) << "QSM cylinder " << c.id;
    SYLVA_CHECK(std::abs(c.axis.norm() - 1.0) <= kAxisCheckTolerance)
        << "QSM cylinder " << c.id << " axis is not a unit vector";
    SYLVA_CHECK(c.length > 0 && std::isfinite(c.length)) << "QSM cylinder " << c.id << " length";
    SYLVA_CHECK(c.radius > 0 && std::isfinite(c.radius)) << "QSM cylinder " << c.id << " radius";
    SYLVA_CHECK(c.branch_order >= 0) << "QSM cylinder " << c.id << " branch_order";
  }
  const int cycle = FindCycle(cylinders);
  SYLVA_CHECK(cycle < 0) << "QSM cylinder " << cylinders[cycle].id << " is on a parent cycle";
}

// ---------------------------------------------------------------------------
// Reading

namespace {

// Splits one CSV line at commas outside double quotes; removes the quotes
// ("" inside quotes is a quote) and surrounding blanks.
std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (ch == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      fields.emplace_back();
    } else if (quoted || (ch != ' ' && ch != '\t') || !fields.back().empty()) {
      fields.back() += ch;
    }
  }
  for (std::string& field : fields) {
    while (!field.empty() && (field.back() == ' ' || field.back() == '\t')) field.pop_back();
  }
  return fields;
}

// One data row with its location, for error messages.
class CsvRow {
 public:
  CsvRow(std::vector<std::string> fields, const std::map<std::string, int>& columns,
         std::string where)
      : fields_(std::move(fields)), columns_(columns), where_(std::move(where)) {}

  const std::string& where() const { return where_; }
  bool Has(const std::string& name) const { return columns_.count(name) > 0; }

  const std::string& Text(const std::string& name) const {
    const int column = columns_.at(name);
    SYLVA_CHECK_INPUT(column < static_cast<int>(fields_.size()), where_)
        << "row has " << fields_.size() << " fields, no '" << name << "'";
    return fields_[column];
  }

  double Double(const std::string& name) const {
    const double value = Parse<double>(name, "a number");
    SYLVA_CHECK_INPUT(std::isfinite(value), where_) << name << " is not finite";
    return value;
  }

  int64_t Int(const std::string& name) const { return Parse<int64_t>(name, "an integer"); }

 private:
  // The whole field as a T (std::from_chars: locale-independent).
  template <typename T>
  T Parse(const std::string& name, const char* what) const {
    const std::string& text = Text(name);
    T value{};
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    SYLVA_CHECK_INPUT(error == std::errc() && end == text.data() + text.size() && !text.empty(),
                      where_)
        << name << " '" << text << "' is not " << what;
    return value;
  }

  std::vector<std::string> fields_;
  const std::map<std::string, int>& columns_;
  std::string where_;
};

QsmCylinder ParseCylinder(const CsvRow& row) {
  QsmCylinder c;
  c.id = row.Int("id");
  c.parent_id = row.Int("parent_id");
  SYLVA_CHECK_INPUT(c.id > 0, row.where()) << "id must be > 0 (0 means 'no parent')";
  SYLVA_CHECK_INPUT(c.parent_id >= 0, row.where()) << "parent_id must be >= 0";
  SYLVA_CHECK_INPUT(c.parent_id != c.id, row.where())
      << "cylinder " << c.id << " is its own parent";
  c.start = {row.Double("start_x"), row.Double("start_y"), row.Double("start_z")};
  c.axis = {row.Double("axis_x"), row.Double("axis_y"), row.Double("axis_z")};
  const double norm = c.axis.norm();
  SYLVA_CHECK_INPUT(std::abs(norm - 1.0) <= kAxisReadTolerance, row.where())
      << "axis has length " << norm << ", not 1";
  c.axis /= norm;
  c.length = row.Double("length");
  c.radius = row.Double("radius");
  SYLVA_CHECK_INPUT(c.length > 0, row.where()) << "length must be > 0";
  SYLVA_CHECK_INPUT(c.radius > 0, row.where()) << "radius must be > 0";
  c.branch = row.Int("branch");
  const int64_t order = row.Int("branch_order");
  SYLVA_CHECK_INPUT(order >= 0 && order < (1 << 20), row.where()) << "bad branch_order " << order;
  c.branch_order = static_cast<int>(order);
  return c;
}

// Header: column name -> index; every required column present.
std::map<std::string, int> ParseHeader(const std::string& line, const std::string& where) {
  std::map<std::string, int> columns;
  const std::vector<std::string> names = SplitCsvLine(line);
  for (int i = 0; i < static_cast<int>(names.size()); ++i) {
    SYLVA_CHECK_INPUT(columns.emplace(names[i], i).second, where)
        << "column '" << names[i] << "' appears twice";
  }
  for (const char* name : kColumns) {
    SYLVA_CHECK_INPUT(columns.count(name) > 0, where)
        << "missing column '" << name << "' (a QSM cylinder table needs id, parent_id, "
        << "start_x/y/z, axis_x/y/z, length, radius, branch, branch_order)";
  }
  return columns;
}

// A per-row text column that must be the same on every row.
void ReadUniformColumn(const CsvRow& row, const std::string& name, bool first, std::string* value) {
  if (!row.Has(name)) return;
  const std::string& text = row.Text(name);
  if (first) *value = text;
  SYLVA_CHECK_INPUT(text == *value, row.where())
      << name << " '" << text << "' differs from the first row's '" << *value << "'";
}

// Topology checks with the offending line.
void CheckTopology(const std::vector<QsmCylinder>& cylinders, const std::vector<int>& lines,
                   const std::string& source) {
  std::unordered_map<int64_t, int> index;
  for (int i = 0; i < static_cast<int>(cylinders.size()); ++i) {
    const auto [it, inserted] = index.emplace(cylinders[i].id, i);
    SYLVA_CHECK_INPUT(inserted, source + ":" + std::to_string(lines[i]))
        << "id " << cylinders[i].id << " also on line " << lines[it->second];
  }
  for (int i = 0; i < static_cast<int>(cylinders.size()); ++i) {
    const int64_t parent = cylinders[i].parent_id;
    SYLVA_CHECK_INPUT(parent == 0 || index.count(parent) > 0,
                      source + ":" + std::to_string(lines[i]))
        << "parent_id " << parent << " is no cylinder's id";
  }
  const int cycle = FindCycle(cylinders);
  SYLVA_CHECK_INPUT(cycle < 0, source + ":" + std::to_string(cycle < 0 ? 0 : lines[cycle]))
      << "cylinder " << (cycle < 0 ? 0 : cylinders[cycle].id)
      << " is on a cycle of parents (no root below it)";
}

}  // namespace

QsmModel ReadQsmCsv(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::istringstream in(ReadFileToString(path));
  std::string line;
  int line_number = 0;
  std::map<std::string, int> columns;
  QsmModel qsm;
  std::vector<int> lines;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number == 1 && line.rfind(kUtf8Bom, 0) == 0) line.erase(0, 3);  // Excel's
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const std::string where = source + ":" + std::to_string(line_number);
    if (columns.empty()) {
      columns = ParseHeader(line, where);
      continue;
    }
    const CsvRow row(SplitCsvLine(line), columns, where);
    qsm.cylinders.push_back(ParseCylinder(row));
    ReadUniformColumn(row, "radius_source", lines.empty(), &qsm.radius_source);
    ReadUniformColumn(row, "position_source", lines.empty(), &qsm.position_source);
    ReadUniformColumn(row, "branching_source", lines.empty(), &qsm.branching_source);
    ReadUniformColumn(row, "units", lines.empty(), &qsm.units);
    lines.push_back(line_number);
  }
  SYLVA_CHECK_INPUT(!columns.empty(), source) << "empty file; expected a QSM cylinder table header";
  CheckTopology(qsm.cylinders, lines, source);
  return qsm;
}

// ---------------------------------------------------------------------------
// Writing

namespace {

// Shortest text that reads back as the same double.
void AppendDouble(double value, std::string* out) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

// Quotes a text field if it holds a comma or a quote.
std::string CsvText(const std::string& text) {
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char ch : text) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return quoted + "\"";
}

}  // namespace

void WriteQsmCsv(const std::filesystem::path& path, const QsmModel& qsm) {
  qsm.Check();
  std::string out;
  for (const char* name : kColumns) out += std::string(name) + ",";
  out += "radius_source,position_source,branching_source,units\n";
  const std::string tail = CsvText(qsm.radius_source) + "," + CsvText(qsm.position_source) + "," +
                           CsvText(qsm.branching_source) + "," + CsvText(qsm.units) + "\n";
  for (const QsmCylinder& c : qsm.cylinders) {
    out += std::to_string(c.id) + "," + std::to_string(c.parent_id);
    for (int k = 0; k < 3; ++k) AppendDouble(c.start[k], &(out += ","));
    for (int k = 0; k < 3; ++k) AppendDouble(c.axis[k], &(out += ","));
    AppendDouble(c.length, &(out += ","));
    AppendDouble(c.radius, &(out += ","));
    out += "," + std::to_string(c.branch) + "," + std::to_string(c.branch_order) + "," + tail;
  }
  AtomicWriteString(path, out);
}

// ---------------------------------------------------------------------------
// QSM -> skeletons

namespace {

bool Coincide(const Eigen::Vector3d& a, const QsmCylinder& parent) {
  const Eigen::Vector3d end = parent.End();
  const double scale = std::max(parent.length, end.cwiseAbs().maxCoeff());
  return (a - end).norm() <= kCoincidenceTolerance * scale;
}

// Adds a node to `part` with its cylinder and branch ids.
int AddQsmNode(const Eigen::Vector3d& position, double radius, int parent_idx, int order,
               int64_t cylinder_id, int64_t branch_id, QsmSkeleton* part) {
  part->cylinder_ids.push_back(cylinder_id);
  part->branch_ids.push_back(branch_id);
  return part->skeleton.AddNode(position, radius, parent_idx, order);
}

// Where a child cylinder attaches: a node of its parent, and whether it
// starts there (shared node) or at a connector node of its own.
struct Attachment {
  int node = -1;
  bool connector = true;
};

// Parameter in [0, 1] along `parent` where `child` attaches: 1 (the end) for
// a child continuing the parent's branch, else the projection of the child's
// start, kept kSplitSnap from the ends.
double AttachParameter(const QsmCylinder& child, const QsmCylinder& parent) {
  if (child.branch == parent.branch || Coincide(child.start, parent)) return 1.0;
  const double t = (child.start - parent.start).dot(parent.axis) / parent.length;
  if (t > 1.0 - kSplitSnap) return 1.0;
  return std::max(t, kSplitSnap);
}

// Adds the nodes of cylinder `c` after its start node `start`: one split node
// per distinct interior attachment of its children (in order along it), then
// its end node. Returns where each child (children[c][k]) attaches.
std::vector<Attachment> AddCylinderNodes(const QsmModel& qsm, const std::vector<int>& children,
                                         int c, int start, QsmSkeleton* part) {
  const QsmCylinder& cyl = qsm.cylinders[c];
  std::vector<double> t(children.size());
  for (size_t k = 0; k < children.size(); ++k)
    t[k] = AttachParameter(qsm.cylinders[children[k]], cyl);
  std::vector<double> splits;
  for (double tk : t) {
    if (tk < 1.0) splits.push_back(tk);
  }
  std::sort(splits.begin(), splits.end());
  splits.erase(std::unique(splits.begin(), splits.end()), splits.end());
  std::vector<int> split_nodes;
  int previous = start;
  for (double ts : splits) {
    previous = AddQsmNode(cyl.start + ts * cyl.length * cyl.axis, cyl.radius, previous,
                          cyl.branch_order, cyl.id, cyl.branch, part);
    split_nodes.push_back(previous);
  }
  const int end =
      AddQsmNode(cyl.End(), cyl.radius, previous, cyl.branch_order, cyl.id, cyl.branch, part);
  std::vector<Attachment> attachments(children.size());
  for (size_t k = 0; k < children.size(); ++k) {
    if (t[k] == 1.0) {
      attachments[k] = {end, !Coincide(qsm.cylinders[children[k]].start, cyl)};
    } else {
      const size_t at = std::lower_bound(splits.begin(), splits.end(), t[k]) - splits.begin();
      attachments[k] = {split_nodes[at], true};
    }
  }
  return attachments;
}

// Adds the cylinders below root cylinder `root`, depth-first (children in
// table order), to `part`.
void AddCylinderTree(const QsmModel& qsm, const std::vector<std::vector<int>>& children, int root,
                     const QsmToSkeletonOptions& options, QsmSkeleton* part) {
  struct Item {
    int cylinder;
    Attachment attachment;  // node -1 for the root
    int parent;             // cylinder index, -1 for the root
  };
  std::vector<Item> stack = {{root, {}, -1}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const QsmCylinder& c = qsm.cylinders[item.cylinder];
    int start = item.attachment.node;
    bool merges = start >= 0 && (c.start - part->skeleton.nodes[start].position).norm() <=
                                    options.merge_fraction * c.radius;
    if (start >= 0 && options.merge_inside_parent) {
      const QsmCylinder& p = qsm.cylinders[item.parent];
      merges = merges || SegmentDistance2(c.start, p.start, p.End()) <= p.radius * p.radius;
    }
    if (item.attachment.connector && !merges) {
      start = AddQsmNode(c.start, c.radius, item.attachment.node, c.branch_order, 0, 0, part);
    }
    const std::vector<int>& below = children[item.cylinder];
    const std::vector<Attachment> attachments =
        AddCylinderNodes(qsm, below, item.cylinder, start, part);
    for (size_t k = below.size(); k-- > 0;) {
      stack.push_back({below[k], attachments[k], item.cylinder});
    }
  }
}

}  // namespace

void QsmToSkeletonOptions::Check() const {
  SYLVA_CHECK_INPUT(merge_fraction >= 0 && std::isfinite(merge_fraction),
                    "QsmToSkeleton.merge_fraction")
      << "must be >= 0";
}

std::vector<QsmSkeleton> SkeletonsFromQsm(const QsmModel& qsm,
                                          const QsmToSkeletonOptions& options) {
  options.Check();
  qsm.Check();
  const std::unordered_map<int64_t, int> index = IndexById(qsm.cylinders);
  std::vector<std::vector<int>> children(qsm.cylinders.size());
  std::vector<int> roots;
  for (int i = 0; i < static_cast<int>(qsm.cylinders.size()); ++i) {
    const int64_t parent = qsm.cylinders[i].parent_id;
    if (parent == 0) {
      roots.push_back(i);
    } else {
      children[index.at(parent)].push_back(i);
    }
  }
  std::vector<QsmSkeleton> parts(roots.size());
  for (size_t r = 0; r < roots.size(); ++r) {
    parts[r].skeleton.radius_source = qsm.radius_source;
    AddCylinderTree(qsm, children, roots[r], options, &parts[r]);
    parts[r].skeleton.Check();
  }
  return parts;
}

// ---------------------------------------------------------------------------
// Skeletons -> QSM

namespace {

// The cylinder from `from` to `to` (distinct points).
QsmCylinder CylinderBetween(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius) {
  QsmCylinder c;
  c.start = from;
  c.length = (to - from).norm();
  c.axis = (to - from) / c.length;
  c.radius = radius;
  return c;
}

// Id of the cylinder node i lies on (its end or one of its split nodes),
// walking up over connector nodes; 0 at a root.
int64_t CylinderAt(const QsmSkeleton& part, int i) {
  while (i >= 0 && part.cylinder_ids[i] == 0) i = part.skeleton.nodes[i].parent_idx;
  return i < 0 ? 0 : part.cylinder_ids[i];
}

}  // namespace

QsmModel QsmFromSkeletons(const std::vector<QsmSkeleton>& parts, const std::string& units) {
  QsmModel qsm;
  qsm.units = units;
  if (!parts.empty()) qsm.radius_source = parts.front().skeleton.radius_source;
  for (const QsmSkeleton& part : parts) {
    const SkeletonGraph& skeleton = part.skeleton;
    skeleton.Check();
    SYLVA_CHECK(static_cast<int>(part.cylinder_ids.size()) == skeleton.NumNodes() &&
                static_cast<int>(part.branch_ids.size()) == skeleton.NumNodes())
        << "QsmSkeleton needs a cylinder and branch id per node";
    const std::vector<std::vector<int>> children = skeleton.Children();
    for (int i = 0; i < skeleton.NumNodes(); ++i) {
      const int64_t id = part.cylinder_ids[i];
      if (id == 0 || std::any_of(children[i].begin(), children[i].end(),
                                 [&](int child) { return part.cylinder_ids[child] == id; })) {
        continue;  // not the end node of a cylinder
      }
      // Up over the cylinder's split nodes to the node it starts at.
      int start = skeleton.nodes[i].parent_idx;
      while (start >= 0 && part.cylinder_ids[start] == id) start = skeleton.nodes[start].parent_idx;
      SYLVA_CHECK(start >= 0) << "cylinder " << id << " has no start node";
      const SkeletonNode& node = skeleton.nodes[i];
      QsmCylinder c = CylinderBetween(skeleton.nodes[start].position, node.position, node.radius);
      c.id = id;
      c.parent_id = CylinderAt(part, start);
      c.branch = part.branch_ids[i];
      c.branch_order = node.order;
      qsm.cylinders.push_back(c);
    }
  }
  std::sort(qsm.cylinders.begin(), qsm.cylinders.end(),
            [](const QsmCylinder& a, const QsmCylinder& b) { return a.id < b.id; });
  qsm.Check();
  return qsm;
}

QsmModel QsmFromSkeleton(const SkeletonGraph& skeleton, const std::string& units) {
  skeleton.Check();
  QsmModel qsm;
  qsm.units = units;
  qsm.radius_source = skeleton.radius_source;
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = skeleton.BranchAxes(&orders);
  // Id of the cylinder ending at each node (0: none, the root or after a
  // zero-length edge, which inherits its parent's).
  std::vector<int64_t> ending(skeleton.nodes.size(), 0);
  for (size_t a = 0; a < axes.size(); ++a) {
    for (size_t k = 1; k < axes[a].size(); ++k) {
      const int node = axes[a][k];
      const int parent = axes[a][k - 1];
      const Eigen::Vector3d& from = skeleton.nodes[parent].position;
      const Eigen::Vector3d& to = skeleton.nodes[node].position;
      ending[node] = ending[parent];
      if (from == to) continue;
      QsmCylinder c = CylinderBetween(from, to, skeleton.nodes[node].radius);
      c.id = static_cast<int64_t>(qsm.cylinders.size()) + 1;
      c.parent_id = ending[parent];
      c.branch = static_cast<int64_t>(a) + 1;
      c.branch_order = orders[a];
      qsm.cylinders.push_back(c);
      ending[node] = c.id;
    }
  }
  return qsm;
}

// ---------------------------------------------------------------------------
// Volumes

double QsmCylinderVolumeSum(const QsmModel& qsm) {
  double sum = 0.0;
  for (const QsmCylinder& c : qsm.cylinders) sum += M_PI * c.radius * c.radius * c.length;
  return sum;
}

double QsmUnionVolume(const QsmModel& qsm, int samples_per_cylinder, uint64_t seed) {
  qsm.Check();
  SYLVA_CHECK(samples_per_cylinder > 0) << "samples_per_cylinder must be > 0";
  const std::vector<QsmCylinder>& cylinders = qsm.cylinders;
  if (cylinders.empty()) return 0.0;
  // A hash grid of cells about the median cylinder's size: each cylinder is
  // listed in every cell its bounding box touches.
  std::vector<double> sizes;
  for (const QsmCylinder& c : cylinders) sizes.push_back(std::max(c.length, 2 * c.radius));
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  const double cell = sizes[sizes.size() / 2];
  auto cell_of = [cell](const Eigen::Vector3d& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell)),
                           static_cast<int>(std::floor(p.y() / cell)),
                           static_cast<int>(std::floor(p.z() / cell)));
  };
  auto key = [](const Eigen::Vector3i& c) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(c.x()) & 0x1fffff) << 42) |
           (static_cast<uint64_t>(static_cast<uint32_t>(c.y()) & 0x1fffff) << 21) |
           (static_cast<uint64_t>(static_cast<uint32_t>(c.z()) & 0x1fffff));
  };
  std::unordered_map<uint64_t, std::vector<int>> grid;
  for (int i = 0; i < static_cast<int>(cylinders.size()); ++i) {
    const QsmCylinder& c = cylinders[i];
    const Eigen::Vector3d a = c.start, b = c.End();
    // The disc of radius r across the axis reaches r sqrt(1 - axis_k^2) along k.
    const Eigen::Vector3d reach =
        c.radius * (Eigen::Vector3d::Ones() - c.axis.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
    const Eigen::Vector3i lo = cell_of(a.cwiseMin(b) - reach), hi = cell_of(a.cwiseMax(b) + reach);
    for (int x = lo.x(); x <= hi.x(); ++x) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int z = lo.z(); z <= hi.z(); ++z) grid[key({x, y, z})].push_back(i);
      }
    }
  }
  auto inside = [](const QsmCylinder& c, const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - c.start;
    const double t = d.dot(c.axis);
    return t >= 0 && t <= c.length && (d - t * c.axis).squaredNorm() <= c.radius * c.radius;
  };
  RandomEngine rng(seed);
  double volume = 0.0;
  for (int i = 0; i < static_cast<int>(cylinders.size()); ++i) {
    const QsmCylinder& c = cylinders[i];
    const Eigen::Vector3d helper =
        std::abs(c.axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e1 = c.axis.cross(helper).normalized(), e2 = c.axis.cross(e1);
    int own = 0;
    for (int k = 0; k < samples_per_cylinder; ++k) {
      const double t = rng.Uniform() * c.length, r = std::sqrt(rng.Uniform()) * c.radius;
      const double phi = rng.Uniform() * 2 * M_PI;
      const Eigen::Vector3d p =
          c.start + t * c.axis + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
      const auto it = grid.find(key(cell_of(p)));
      bool earlier = false;
      if (it != grid.end()) {
        for (int j : it->second) {
          if (j >= i) break;  // listed in increasing order
          if (inside(cylinders[j], p)) {
            earlier = true;
            break;
          }
        }
      }
      own += earlier ? 0 : 1;
    }
    volume += M_PI * c.radius * c.radius * c.length * own / samples_per_cylinder;
  }
  return volume;
}

}  // namespace sylva
