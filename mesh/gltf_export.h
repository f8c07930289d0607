// Binary glTF 2.0 (.glb) export of tree meshes, and a reader for them.
//
// WriteGlb writes one mesh with one primitive per material that has
// triangles (TRIANGLES mode, uint32 indices), all primitives sharing one
// POSITION and one NORMAL accessor (area-weighted vertex normals,
// TriangleMesh::VertexNormals). Materials are metallic-roughness PBR
// materials: baseColorFactor = (Material::diffuse_color, 1) (both are linear
// RGB), metallic 0, roughness 1, doubleSided = Material::double_sided
// (leaves). asset.generator is "sylva"; asset.extras carries the caller's
// notes (e.g. "radius_source": "allometric prior", so that whoever opens the
// file knows the branch radii are an estimate, not a measurement).
//
// Frames: vertex data stays in sylva's world frame (+Z up, world units,
// metres when the scale is known); glTF scenes are +Y up, so by default the
// mesh's node carries the rotation of -90 degrees about X that maps +Z to +Y.
//
// tinygltf does the encoding (Debian's shared libtinygltf); it stays an
// implementation detail of gltf_export.cc.
#ifndef SYLVA_MESH_GLTF_EXPORT_H_
#define SYLVA_MESH_GLTF_EXPORT_H_

#include <filesystem>
#include <map>
#include <string>

#include "core/types/triangle_mesh.h"

namespace sylva {

struct GltfExportOptions {
  // Notes written as string members of asset.extras (keys non-empty).
  std::map<std::string, std::string> extras;
  // Rotate the scene node so that sylva's +Z up is glTF's +Y up.
  bool y_up = true;

  // Throws InputError("GltfExport.extras", ...) for an empty key.
  void Check() const;
};

// Writes `mesh` to `path` (.glb) atomically (temp file + rename). Throws
// Error if the mesh fails TriangleMesh::Check() or the file cannot be
// written, InputError for bad options. A mesh without triangles gives a
// valid file with its materials and an empty scene.
void WriteGlb(const std::filesystem::path& path, const TriangleMesh& mesh,
              const GltfExportOptions& options = GltfExportOptions());

// Reads the triangles of every mesh primitive in a .glb file into one
// TriangleMesh: positions (float VEC3), indices (uint8/16/32, or none),
// TRIANGLES mode only; materials from name, baseColorFactor and doubleSided
// (a primitive without material gets a grey "default"). Node transforms are
// not applied: files written by WriteGlb come back in sylva's world frame.
// Accessors shared between primitives are read once. `asset_extras`
// (optional) receives asset.extras' string members and "generator".
// Throws InputError naming the file for unreadable or unsupported content.
TriangleMesh ReadGlb(const std::filesystem::path& path,
                     std::map<std::string, std::string>* asset_extras = nullptr);

}  // namespace sylva

#endif  // SYLVA_MESH_GLTF_EXPORT_H_
