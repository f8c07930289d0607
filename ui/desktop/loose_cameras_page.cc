#include "ui/desktop/loose_cameras_page.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGraphicsEllipseItem>
#include <QGraphicsScene>
#include <QGraphicsSimpleTextItem>
#include <QGraphicsView>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QMouseEvent>
#include <QTableWidget>
#include <QVBoxLayout>
#include <exception>

#include "reconstruct/registration/loose_setup_io.h"

namespace sylva {
namespace {

enum Column { kUseColumn, kNameColumn, kAzimuthColumn, kProjectionColumn };
constexpr double kMarkRadius = 4.0;  // view pixels

}  // namespace

LooseCamerasPage::LooseCamerasPage(std::function<std::filesystem::path()> photos_dir,
                                   QWidget* parent)
    : QWizardPage(parent), photos_dir_(std::move(photos_dir)) {
  setTitle("Manual cameras");
  setSubTitle(
      "Tick 2-4 photos and give each its azimuth around the tree (0 = from +X, 90 = from +Y). "
      "Then click the tree's base, its top and any other point you name on each photo showing "
      "it.");
  photos_ = new QTableWidget(0, 4);
  photos_->setHorizontalHeaderLabels({"Use", "Photo", "Azimuth °", "Projection"});
  photos_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  photos_->verticalHeader()->hide();
  photos_->setMinimumWidth(380);
  photos_->setSelectionBehavior(QAbstractItemView::SelectRows);
  connect(photos_, &QTableWidget::currentCellChanged, this, [this](int row) { ShowPhoto(row); });
  points_ = new QComboBox;
  points_->setEditable(true);
  points_->addItems({kLooseBasePoint, kLooseTopPoint});
  points_->setToolTip("The point your clicks place; type a new name for another point");
  tree_height_ = new QDoubleSpinBox;
  tree_height_->setRange(0, 1e4);
  tree_height_->setSpecialValueText("unknown");
  units_ = new QLineEdit("m");
  scene_ = new QGraphicsScene(this);
  view_ = new QGraphicsView(scene_);
  view_->setMinimumSize(300, 300);
  view_->viewport()->installEventFilter(this);
  view_->setCursor(Qt::CrossCursor);
  error_ = new QLabel;
  error_->setWordWrap(true);
  error_->setStyleSheet("color: #c03030");

  auto* form = new QFormLayout;
  form->addRow("Point to click", points_);
  form->addRow("Tree height", tree_height_);
  form->addRow("Units", units_);
  auto* left = new QVBoxLayout;
  left->addWidget(photos_, 1);
  left->addLayout(form);
  auto* layout = new QHBoxLayout(this);
  layout->addLayout(left, 0);
  auto* right = new QVBoxLayout;
  right->addWidget(view_, 1);
  right->addWidget(error_);
  layout->addLayout(right, 1);
}

void LooseCamerasPage::initializePage() {
  const QDir dir(QString::fromStdString(photos_dir_().string()));
  const QStringList names =
      dir.entryList({"*.png", "*.jpg", "*.jpeg", "*.tif", "*.tiff", "*.PNG", "*.JPG", "*.JPEG"},
                    QDir::Files, QDir::Name);
  photos_->setRowCount(0);
  clicks_.clear();
  shown_row_ = -1;
  for (int row = 0; row < names.size(); ++row) {
    photos_->insertRow(row);
    auto* use = new QCheckBox;
    use->setChecked(row < 2);
    photos_->setCellWidget(row, kUseColumn, use);
    auto* name = new QTableWidgetItem(names[row]);
    name->setFlags(name->flags() & ~Qt::ItemIsEditable);
    photos_->setItem(row, kNameColumn, name);
    auto* azimuth = new QDoubleSpinBox;
    azimuth->setRange(-360, 360);
    azimuth->setValue(90.0 * row);
    photos_->setCellWidget(row, kAzimuthColumn, azimuth);
    auto* projection = new QComboBox;
    projection->addItems({"perspective", "orthographic"});
    photos_->setCellWidget(row, kProjectionColumn, projection);
  }
  if (!names.isEmpty()) photos_->setCurrentCell(0, kNameColumn);
}

void LooseCamerasPage::UsePhoto(int row, double azimuth_deg, bool orthographic) {
  qobject_cast<QCheckBox*>(photos_->cellWidget(row, kUseColumn))->setChecked(true);
  qobject_cast<QDoubleSpinBox*>(photos_->cellWidget(row, kAzimuthColumn))->setValue(azimuth_deg);
  qobject_cast<QComboBox*>(photos_->cellWidget(row, kProjectionColumn))
      ->setCurrentIndex(orthographic ? 1 : 0);
}

void LooseCamerasPage::ShowPhoto(int row) {
  if (row < 0 || row >= photos_->rowCount()) return;
  if (photos_->currentRow() != row) photos_->setCurrentCell(row, kNameColumn);  // calls back
  shown_row_ = row;
  const QString name = photos_->item(row, kNameColumn)->text();
  const QImage photo(QDir(QString::fromStdString(photos_dir_().string())).filePath(name));
  scene_->clear();
  scene_->addPixmap(QPixmap::fromImage(photo));
  scene_->setSceneRect(QRectF(0, 0, photo.width(), photo.height()));
  view_->fitInView(scene_->sceneRect(), Qt::KeepAspectRatio);
  DrawMarks();
}

void LooseCamerasPage::SetCurrentPoint(const QString& name) { points_->setCurrentText(name); }

bool LooseCamerasPage::eventFilter(QObject* object, QEvent* event) {
  if (object != view_->viewport() || event->type() != QEvent::MouseButtonPress || shown_row_ < 0) {
    return QWizardPage::eventFilter(object, event);
  }
  const auto* mouse = static_cast<QMouseEvent*>(event);
  if (mouse->button() != Qt::LeftButton) return false;
  const QString point = points_->currentText().trimmed();
  if (point.isEmpty()) return true;
  if (points_->findText(point) < 0) points_->addItem(point);
  const QString photo = photos_->item(shown_row_, kNameColumn)->text();
  clicks_[{point, photo}] = view_->mapToScene(mouse->position().toPoint());
  DrawMarks();
  return true;
}

void LooseCamerasPage::DrawMarks() {
  for (QGraphicsItem* item : scene_->items()) {
    if (item->type() != QGraphicsPixmapItem::Type) delete item;
  }
  if (shown_row_ < 0) return;
  const QString photo = photos_->item(shown_row_, kNameColumn)->text();
  const double r = kMarkRadius / std::max(1e-6, view_->transform().m11());
  for (const auto& [key, position] : clicks_) {
    if (key.second != photo) continue;
    QPen pen(QColor(255, 60, 60));
    pen.setCosmetic(true);
    scene_->addEllipse(QRectF(position - QPointF(r, r), QSizeF(2 * r, 2 * r)), pen);
    QGraphicsSimpleTextItem* label = scene_->addSimpleText(key.first);
    label->setBrush(QColor(255, 60, 60));
    label->setFlag(QGraphicsItem::ItemIgnoresTransformations);
    label->setPos(position + QPointF(r, r));
  }
}

LooseSetup LooseCamerasPage::Setup() const {
  LooseSetup setup;
  setup.source = "the manual cameras page";
  setup.tree_height = tree_height_->value();
  if (setup.tree_height > 0) setup.units = units_->text().trimmed().toStdString();
  std::map<QString, int> photo_index;
  for (int row = 0; row < photos_->rowCount(); ++row) {
    if (!qobject_cast<QCheckBox*>(photos_->cellWidget(row, kUseColumn))->isChecked()) continue;
    LoosePhoto photo;
    photo.name = photos_->item(row, kNameColumn)->text().toStdString();
    photo.azimuth_deg =
        qobject_cast<QDoubleSpinBox*>(photos_->cellWidget(row, kAzimuthColumn))->value();
    photo.projection =
        qobject_cast<QComboBox*>(photos_->cellWidget(row, kProjectionColumn))->currentIndex() == 1
            ? LooseProjection::kOrthographic
            : LooseProjection::kPerspective;
    photo_index[photos_->item(row, kNameColumn)->text()] = static_cast<int>(setup.photos.size());
    setup.photos.push_back(photo);
  }
  for (const auto& [key, position] : clicks_) {
    const auto photo = photo_index.find(key.second);
    if (photo == photo_index.end()) continue;  // a photo not used
    int point = setup.FindPoint(key.first.toStdString());
    if (point < 0) {
      point = static_cast<int>(setup.points.size());
      setup.points.push_back({key.first.toStdString(), {}});
    }
    setup.points[point].observations.push_back(
        {photo->second, Eigen::Vector2d(position.x(), position.y())});
  }
  return setup;
}

bool LooseCamerasPage::validatePage() {
  try {
    const LooseSetup setup = Setup();
    setup.Check();
    written_file_ = std::filesystem::path(temp_.path().toStdString()) / "loose_cameras.json";
    WriteLooseSetup(written_file_, setup);
    error_->clear();
    return true;
  } catch (const std::exception& error) {
    error_->setText(QString::fromStdString(error.what()));
    return false;
  }
}

}  // namespace sylva
