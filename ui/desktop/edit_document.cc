#include "ui/desktop/edit_document.h"

#include <QUndoCommand>
#include <exception>

#include "ui/pipeline/project.h"

namespace sylva {
namespace {

// One finished stroke on one photo.
class EditCommand : public QUndoCommand {
 public:
  EditCommand(EditDocument* document, std::string photo_name, PhotoEdits before, PhotoEdits after,
              unsigned layers, const QString& text)
      : QUndoCommand(text),
        document_(document),
        photo_name_(std::move(photo_name)),
        before_(std::move(before)),
        after_(std::move(after)),
        layers_(layers) {}

  void undo() override { document_->Set(photo_name_, before_, layers_); }
  void redo() override { document_->Set(photo_name_, after_, layers_); }

 private:
  EditDocument* document_;
  std::string photo_name_;
  PhotoEdits before_, after_;  // QImage layers are shared until changed
  unsigned layers_;
};

}  // namespace

EditDocument::EditDocument(const Project* project, QObject* parent)
    : QObject(parent), project_(project) {}

const PhotoEdits& EditDocument::Edits(const std::string& photo_name, int width, int height) {
  auto it = edits_.find(photo_name);
  if (it == edits_.end()) {
    it = edits_.emplace(photo_name, LoadPhotoEdits(*project_, photo_name, width, height)).first;
  }
  return it->second;
}

void EditDocument::Commit(const std::string& photo_name, const PhotoEdits& before,
                          const PhotoEdits& after, unsigned layers, const QString& text) {
  undo_stack_.push(new EditCommand(this, photo_name, before, after, layers, text));
}

void EditDocument::Set(const std::string& photo_name, const PhotoEdits& edits, unsigned layers) {
  PhotoEdits& held = edits_[photo_name];
  held.width = edits.width;
  held.height = edits.height;
  if (layers & kDensityLayer) held.density = edits.density;
  if (layers & kTrimapLayer) held.trimap = edits.trimap;
  if (layers & kStrokesLayer) held.strokes = edits.strokes, held.root = edits.root;
  if (layers & kCrownLayer) held.crowns = edits.crowns;
  try {
    SavePhotoEdits(*project_, photo_name, held, layers);
  } catch (const std::exception& error) {
    emit SaveFailed(QString::fromStdString(error.what()));
  }
  emit Changed(QString::fromStdString(photo_name));
}

}  // namespace sylva
