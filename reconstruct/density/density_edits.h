// Density painted on a photo (thesis 3.3, "sketched density", Fig. 3.12):
// where a photo lies (an occluding neighbour, winter branches, a hole in the
// crown) a person paints opacity in or out, and the density stage reads the
// painted matte instead of the computed one there.
//
// An edit is an image at the photo's size with alpha: grey + alpha or RGBA
// (the grey value is the mean of R, G, B). Alpha is how strongly the edit
// replaces the matte (0 = untouched; soft brushes give partial alpha), the
// grey value is the opacity painted (1 = add density, 0 = remove):
//
//   matte' = (1 - alpha) * matte + alpha * grey
//
// In a project: PROJECT/edits/density/<photo name without extension>.png.
#ifndef SYLVA_RECONSTRUCT_DENSITY_DENSITY_EDITS_H_
#define SYLVA_RECONSTRUCT_DENSITY_DENSITY_EDITS_H_

#include <string>

#include "core/types/float_image.h"

namespace sylva {

// Mixes `edit` into `matte` (1 channel) as above. Throws InputError naming
// `source` if the edit has no alpha (1 or 3 channels) or differs in size.
void ApplyDensityEdit(const FloatImage& edit, const std::string& source, FloatImage* matte);

// The opacity an edit added: max(0, edited - computed) per pixel, for mattes
// of one size (1 channel): where a person painted the tree in.
FloatImage AddedOpacity(const FloatImage& edited, const FloatImage& computed);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_DENSITY_EDITS_H_
