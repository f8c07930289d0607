#include "ui/desktop/overlays.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>

#include "core/io/attractor_io.h"
#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "ui/pipeline/project.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// A comparison picture's pixel is predicted where its red channel is high
// (ui/pipeline/report.cc: 0.9 or 0.95 there, at most 0.25 elsewhere).
constexpr int kPredictedRedMin = 200;
constexpr double kOverlayFillAlpha = 0.12;

bool IsFile(const fs::path& path) {
  std::error_code ec;
  return !path.empty() && fs::is_regular_file(path, ec);
}

}  // namespace

QImage LoadPhoto(const Project& project, const std::string& photo_name) {
  const fs::path path = project.PhotoPath(photo_name);
  QImage image(QString::fromStdString(path.string()));
  if (!image.isNull()) return image.convertToFormat(QImage::Format_ARGB32);
  const FloatImage pixels = ReadImage(path);  // throws InputError naming the file
  image = QImage(pixels.width(), pixels.height(), QImage::Format_ARGB32);
  const int c = pixels.channels();
  for (int y = 0; y < pixels.height(); ++y) {
    QRgb* row = reinterpret_cast<QRgb*>(image.scanLine(y));
    for (int x = 0; x < pixels.width(); ++x) {
      const auto v = [&](int k) {
        return static_cast<int>(std::lround(std::clamp(pixels.at(x, y, k), 0.f, 1.f) * 255));
      };
      const int r = v(0), g = c >= 3 ? v(1) : r, b = c >= 3 ? v(2) : r;
      row[x] = qRgba(r, g, b, (c == 2 || c == 4) ? v(c - 1) : 255);
    }
  }
  return image;
}

QImage MatteOverlay(const Project& project, const std::string& photo_name) {
  const fs::path path = project.MattePath(photo_name);
  if (!IsFile(path)) return {};
  const FloatImage matte = ReadMatte(path);
  QImage image(matte.width(), matte.height(), QImage::Format_ARGB32);
  for (int y = 0; y < matte.height(); ++y) {
    QRgb* row = reinterpret_cast<QRgb*>(image.scanLine(y));
    for (int x = 0; x < matte.width(); ++x) {
      const int alpha = static_cast<int>(std::lround(std::clamp(matte.at(x, y), 0.f, 1.f) * 150));
      row[x] = qRgba(60, 150, 255, alpha);
    }
  }
  return image;
}

QImage ReportSilhouetteOverlay(const Project& project, const std::string& kind,
                               const std::string& photo_name, QRgb color) {
  const fs::path path =
      project.OutDir() / "report" / kind / fs::path(photo_name).replace_extension(".png");
  if (!IsFile(path)) return {};
  const QImage picture =
      QImage(QString::fromStdString(path.string())).convertToFormat(QImage::Format_RGB32);
  if (picture.isNull()) return {};
  // The silhouette's outline (predicted pixels with a non-predicted
  // neighbour) over a faint fill, so the photo stays visible.
  const auto predicted = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= picture.width() || y >= picture.height()) return false;
    return qRed(picture.pixel(x, y)) >= kPredictedRedMin;
  };
  QImage image(picture.size(), QImage::Format_ARGB32);
  const QRgb fill = qRgba(qRed(color), qGreen(color), qBlue(color),
                          static_cast<int>(std::lround(255 * kOverlayFillAlpha)));
  const QRgb edge = qRgba(qRed(color), qGreen(color), qBlue(color), 255);
  for (int y = 0; y < picture.height(); ++y) {
    QRgb* out = reinterpret_cast<QRgb*>(image.scanLine(y));
    for (int x = 0; x < picture.width(); ++x) {
      if (!predicted(x, y)) {
        out[x] = 0;
        continue;
      }
      bool border = false;
      for (int dy = -1; dy <= 1 && !border; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) border = border || !predicted(x + dx, y + dy);
      }
      out[x] = border ? edge : fill;
    }
  }
  return image;
}

QPainterPath AttractorPath(const Project& project, const std::string& photo_name) {
  QPainterPath path;
  const fs::path file = project.AttractorGraphPath(photo_name);
  if (!IsFile(file)) return path;
  const AttractorGraph2D graph = ReadAttractorGraphJson(file);
  for (const auto& [from, to] : graph.Segments()) {
    path.moveTo(from.x(), from.y());
    path.lineTo(to.x(), to.y());
  }
  return path;
}

std::map<std::string, ViewScores> ReadViewScores(const Project& project) {
  std::map<std::string, ViewScores> scores;
  const fs::path path = project.OutDir() / "report.json";
  if (!IsFile(path)) return scores;
  const Json json = ReadJsonFile(path);
  if (!json.contains("views") || !json["views"].is_array()) return scores;
  for (const Json& view : json["views"]) {
    if (!view.contains("name") || !view["name"].is_string()) continue;
    ViewScores& s = scores[view["name"].get<std::string>()];
    if (view.contains("iou") && view["iou"].is_number()) s.density_iou = view["iou"].get<double>();
    if (view.contains("mesh") && view["mesh"].contains("iou") && view["mesh"]["iou"].is_number()) {
      s.mesh_iou = view["mesh"]["iou"].get<double>();
    }
    s.held_out = view.value("held_out", false);
  }
  return scores;
}

}  // namespace sylva
