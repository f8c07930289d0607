// The automatic trimap (internal to reconstruct/matting; the public entry
// points are in matting.h).
#ifndef SYLVA_RECONSTRUCT_MATTING_TRIMAP_H_
#define SYLVA_RECONSTRUCT_MATTING_TRIMAP_H_

#include "core/types/float_image.h"
#include "reconstruct/matting/matting.h"

namespace sylva {

// Throws InputError naming `what` unless `photo` is an RGB or RGBA image of
// at least 8x8 pixels with finite values.
void CheckPhoto(const FloatImage& photo, const char* what);
// CheckPhoto for the photo and, if not empty, the background photo, which
// must also have the photo's size.
void CheckPhotos(const FloatImage& photo, const FloatImage& background_photo);

// ComputeTrimap with a painted hint (may be empty; already checked) that
// GrabCut uses as hard constraints. Fills the trimap fields of `summary`
// (trimap_source, backdrop_rgb, border_agreement) if not null.
FloatImage ComputeAutomaticTrimap(const FloatImage& photo, const MattingOptions& options,
                                  const FloatImage& background_photo, const FloatImage& hint,
                                  MattingSummary* summary);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_TRIMAP_H_
