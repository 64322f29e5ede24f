#pragma once
// preview.glb: the mesh with one homogeneous stand-in for the fitted
// material, in glTF's physically based model (core metallic–roughness with
// KHR_materials_transmission, KHR_materials_volume and KHR_materials_ior),
// for web and real-time viewers (docs/preview.md). glTF's volume absorbs but
// does not scatter, so the stone's look is split the way such a viewer
// draws it: a diffuse part (what the medium scatters back) and a transmitted
// part (what comes out the far side), from a slab of the object's mean
// chord length (volume/slab_reflectance.h).

#include "jade/geometry/mesh.h"

#include <array>
#include <string>

namespace jade {

struct GltfPreviewMaterial {
    std::array<double, 3> base_color{1, 1, 1};         // baseColorFactor (RGB, linear)
    double transmission = 0;                           // transmissionFactor
    std::array<double, 3> attenuation_color{1, 1, 1};  // KHR_materials_volume, over attenuation_distance
    double attenuation_distance = 1;
    double thickness = 1;                              // thicknessFactor, mesh units
    double ior = 1.5;
    // What it stands for, kept in the material's extras and in report.json.
    std::array<double, 3> sigma_s{0, 0, 0}, sigma_a{0, 0, 0};  // per mesh unit
    double g = 0;
    std::array<double, 3> slab_R{0, 0, 0}, slab_T{0, 0, 0};    // the slab's diffuse R and T
};

// The viewer's diffuse lobe carries (1 − t)·base and its transmission
// t·base·attenuation. Per channel the slab's R and T are matched:
// t = max over channels of T/(R + T) (the largest transmitted share, so that
// every attenuation is ≤ 1), base = R/(1 − t) (clipped to 1) and
// attenuation = T/(t·base) (at least 1/1024: a viewer takes its logarithm),
// over a distance and thickness both the mean chord. `thickness` > 0,
// coefficients per mesh unit, `ior` the boundary's (1 when index-matched).
GltfPreviewMaterial gltf_preview_material(const std::array<double, 3>& sigma_s,
                                          const std::array<double, 3>& sigma_a, double g, double ior,
                                          double thickness);

// The mesh (positions, normals, triangles) with the material, as one binary
// glTF written whole or not at all.
void write_preview_glb(const std::string& path, const TriangleMesh& mesh, const GltfPreviewMaterial& material);

}  // namespace jade
