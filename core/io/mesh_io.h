// Wavefront OBJ triangle meshes with a companion .mtl for the materials.
//
// WriteObj writes `tree.obj` and, beside it, `tree.mtl`:
//   # tree.obj                     # tree.mtl
//   mtllib tree.mtl                newmtl bark
//   v 0.1 0.2 0.3                  Kd 0.35 0.25 0.17     (linear RGB in [0, 1])
//   ...                            # sylva double_sided 0
//   usemtl bark                    newmtl leaves
//   f 1 2 3                        ...
// Vertices are written with 9 significant digits, which reproduces every
// float exactly, and faces in the mesh's own order with a `usemtl` wherever the
// material changes, so ReadObj(WriteObj(mesh)) gives back the same mesh.
// Material::double_sided has no MTL keyword; it travels as the comment above,
// which other readers ignore.
#ifndef SYLVA_CORE_IO_MESH_IO_H_
#define SYLVA_CORE_IO_MESH_IO_H_

#include <filesystem>

#include "core/types/triangle_mesh.h"

namespace sylva {

// Writes `path` (the .obj) and the .mtl with the same stem beside it, each
// atomically. Throws Error if the mesh fails TriangleMesh::Check().
void WriteObj(const std::filesystem::path& path, const TriangleMesh& mesh);

// Reads an OBJ file: `v`, `f` (polygons are fan-triangulated; v, v/vt, v//vn,
// v/vt/vn and negative indices accepted), `usemtl` and `mtllib` (Kd colours
// from the .mtl, relative to the .obj's folder); normals, texture coordinates,
// groups and smoothing are ignored. Faces before any `usemtl`, or naming a
// material missing from the .mtl, get a grey default material of that name.
// Throws InputError naming "file:line" for malformed lines and out-of-range
// indices, and the file for a missing .obj or .mtl.
TriangleMesh ReadObj(const std::filesystem::path& path);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_MESH_IO_H_
