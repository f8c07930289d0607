// Pictures the app lays over a photo, made from the project's files: the
// photo itself, its matte, the report's density projection and mesh
// silhouette (out/report/density|mesh/<photo>.png), the attractor graph
// (out/attractors/<photo>.json), and the report's per-view scores. Missing
// outputs give null pictures (the stage has not run yet).
#ifndef SYLVA_UI_DESKTOP_OVERLAYS_H_
#define SYLVA_UI_DESKTOP_OVERLAYS_H_

#include <QImage>
#include <QPainterPath>
#include <map>
#include <optional>
#include <string>

namespace sylva {

class Project;

// The photo as RGBA (InputError naming it if unreadable).
QImage LoadPhoto(const Project& project, const std::string& photo_name);

// The matte as a blue tint whose alpha follows the matte; null if the
// matte does not exist yet (computed mattes before the matte stage).
QImage MatteOverlay(const Project& project, const std::string& photo_name);

// The report's comparison picture of `kind` ("density" or "mesh"), as the
// predicted silhouette: its outline in `color` over a faint fill; null if
// there is none.
QImage ReportSilhouetteOverlay(const Project& project, const std::string& kind,
                               const std::string& photo_name, QRgb color);

// The attractor graph's edges in photo pixels (empty if none).
QPainterPath AttractorPath(const Project& project, const std::string& photo_name);

// Silhouette IoU of a view from out/report.json.
struct ViewScores {
  std::optional<double> density_iou, mesh_iou;
  bool held_out = false;
};
std::map<std::string, ViewScores> ReadViewScores(const Project& project);

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_OVERLAYS_H_
