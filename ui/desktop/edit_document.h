// The edits of every photo of an open project, with undo: each finished
// stroke is one QUndoCommand holding the touched photo's edits before and
// after it; doing or undoing it saves the touched layers at once
// (SavePhotoEdits, atomic), so a kill loses at most the stroke in progress.
// GUI thread only.
#ifndef SYLVA_UI_DESKTOP_EDIT_DOCUMENT_H_
#define SYLVA_UI_DESKTOP_EDIT_DOCUMENT_H_

#include <QObject>
#include <QString>
#include <QUndoStack>
#include <map>
#include <string>

#include "ui/desktop/photo_edits.h"

namespace sylva {

class Project;

class EditDocument : public QObject {
  Q_OBJECT

 public:
  // `project` must outlive the document.
  EditDocument(const Project* project, QObject* parent = nullptr);

  QUndoStack* undo_stack() { return &undo_stack_; }
  const Project& project() const { return *project_; }

  // A photo's edits, read from its files the first time (InputError if
  // one is unreadable).
  const PhotoEdits& Edits(const std::string& photo_name, int width, int height);

  // Pushes one undoable change of `layers` from `before` to `after` (which
  // is saved now).
  void Commit(const std::string& photo_name, const PhotoEdits& before, const PhotoEdits& after,
              unsigned layers, const QString& text);

  // Sets and saves the layers of a photo's edits (used by the commands).
  void Set(const std::string& photo_name, const PhotoEdits& edits, unsigned layers);

 signals:
  void Changed(const QString& photo_name);
  // A save failed (the message names the file); the edit stays in memory.
  void SaveFailed(const QString& message);

 private:
  const Project* project_;
  std::map<std::string, PhotoEdits> edits_;
  QUndoStack undo_stack_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_EDIT_DOCUMENT_H_
