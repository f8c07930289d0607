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
// Leaves: WriteGlb's LeafInstances overload writes the leaf shape once, as a
// second mesh "leaves" (POSITION, NORMAL = +Z of the leaf frame, TEXCOORD_0
// for image leaves), and a node "leaves" that draws it at every leaf's
// transform through the EXT_mesh_gpu_instancing extension (listed in
// extensionsUsed, not extensionsRequired): accessors TRANSLATION (VEC3),
// ROTATION (VEC4 unit quaternion x, y, z, w) and SCALE (VEC3), float, one
// element per leaf, in the same world frame as the bark (the node carries the
// same +Z to +Y rotation). An image leaf's material gets its texture as
// baseColorTexture (PNG, embedded) with alphaMode MASK (cutoff 0.5). Viewers
// without the extension draw one leaf. With instancing off, the leaves are
// baked into the tree mesh as triangles (LeafInstances::Bake, no texture).
//
// tinygltf does the encoding (Debian's shared libtinygltf); it stays an
// implementation detail of gltf_export.cc.
#ifndef SYLVA_MESH_GLTF_EXPORT_H_
#define SYLVA_MESH_GLTF_EXPORT_H_

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "core/types/triangle_mesh.h"
#include "mesh/leaves.h"

namespace sylva {

struct GltfExportOptions {
  // Notes written as string members of asset.extras (keys non-empty).
  std::map<std::string, std::string> extras;
  // Rotate the scene node so that sylva's +Z up is glTF's +Y up.
  bool y_up = true;
  // Leaves as one leaf mesh + per-leaf transforms (EXT_mesh_gpu_instancing);
  // false = baked triangles in the tree mesh.
  bool instance_leaves = true;

  // Throws InputError("GltfExport.extras", ...) for an empty key.
  void Check() const;
};

// Writes `mesh` to `path` (.glb) atomically (temp file + rename). Throws
// Error if the mesh fails TriangleMesh::Check() or the file cannot be
// written, InputError for bad options. A mesh without triangles gives a
// valid file with its materials and an empty scene.
void WriteGlb(const std::filesystem::path& path, const TriangleMesh& mesh,
              const GltfExportOptions& options = GltfExportOptions());

// Writes the tree `mesh` (bark, ...) and `leaves`, instanced or baked as
// options.instance_leaves says (see the header comment).
void WriteGlb(const std::filesystem::path& path, const TriangleMesh& mesh,
              const LeafInstances& leaves, const GltfExportOptions& options = GltfExportOptions());

// Reads the triangles of every mesh primitive in a .glb file into one
// TriangleMesh: positions (float VEC3), indices (uint8/16/32, or none),
// TRIANGLES mode only; materials from name, baseColorFactor and doubleSided
// (a primitive without material gets a grey "default"). Node transforms are
// not applied: files written by WriteGlb come back in sylva's world frame;
// except that a node with EXT_mesh_gpu_instancing (float TRANSLATION /
// ROTATION / SCALE) has its mesh expanded into one copy per instance, each
// under its instance transform (so instanced leaves come back as the baked
// triangles, after the other meshes' triangles). `num_instances` (optional)
// receives the number of instances expanded.
// Accessors shared between primitives are read once. `asset_extras`
// (optional) receives asset.extras' string members and "generator".
// Throws InputError naming the file for unreadable or unsupported content.
TriangleMesh ReadGlb(const std::filesystem::path& path,
                     std::map<std::string, std::string>* asset_extras = nullptr,
                     int64_t* num_instances = nullptr);

// ReadGlb, except that the first node with EXT_mesh_gpu_instancing is not
// expanded: its mesh becomes `leaves`' shape (positions' (x, y) in the leaf
// frame, triangles, and for image leaves TEXCOORD_0 and the decoded 8-bit
// RGBA base colour texture), its first primitive's material `leaves`'
// material, and its transforms `leaves`' instances (so a renderer can draw
// them as instances, mesh/tree_preview.h). The rest comes back as ReadGlb's.
TriangleMesh ReadGlbKeepingLeafInstances(const std::filesystem::path& path, LeafInstances* leaves);

}  // namespace sylva

#endif  // SYLVA_MESH_GLTF_EXPORT_H_
