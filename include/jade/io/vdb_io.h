#pragma once
// The material volume on disk as OpenVDB (docs/design.md, "The .vdb file"). OpenVDB is confined to
// src/io/vdb_io.cpp and src/io/vdb_check.cpp (vdb_check.h): it compiles slowly, and the
// renderer samples plain arrays.
//
// Grids (format 2):
//   sigma_s  Vec3f  scattering coefficient per world unit, RGB         } fog volumes, background 0,
//   sigma_a  Vec3f  absorption coefficient per world unit, RGB         } active inside the mesh
//   density  float  mean extinction (σ_s + σ_a averaged over RGB)      } (grown by a voxel) when
//   color    Vec3f  single-scattering albedo σ_s / σ_t (0 where σ_t = 0) } written with one, else the cube
//   levels   Int32  the material's 8-bit levels r | g << 8 | b << 16, every voxel of the cube:
//                   what jaderender reads back (exactly, and whatever mesh it is rendered in)
// Transform: voxel (i, j, k) is centred at world cube.min + (i + ½, j + ½, k + ½) · h,
// h = cube.side / s, as OpenVDB's index-space convention puts voxel centres at
// integer coordinates; with z_up that world is turned +90° about x (Y-up → Z-up,
// as Blender's glTF importer turns the mesh). File metadata (names prefixed
// "jade:") holds every parameter needed to rebuild the volume and re-render it
// exactly. The levels grid is written last, and jade:levels_digest holds a
// digest of the levels that reading checks (a file cut short is refused).
// Coefficients are stored as half floats where they fit (see write_material_vdb);
// OpenVDB readers (Blender, Houdini) widen them to float transparently.
// Format 1 files (no levels grid: the levels recovered from sigma_s and
// sigma_a over the whole cube) still read.

#include "jade/volume/material_volume.h"
#include "jade/core/spectrum.h"
#include "jade/volume/coefficient_grids.h"
#include "jade/geometry/mesh.h"

#include <string>

namespace jade {

// How the file is laid out for other tools (Blender, Houdini).
struct VdbLayout {
    // Coefficient grids active only inside this mesh (grown by one voxel, for
    // interpolation at the surface); null: the whole cube. The levels always
    // cover the cube.
    const TriangleMesh* mask = nullptr;
    bool z_up = false;  // the grids' world turned Y-up → Z-up
    std::string color_name = "color";  // the albedo grid's name: "color" (Blender) or "Cd" (Houdini)
};

// Writes the grids and the metadata, whole or not at all.
void write_material_vdb(const std::string& path, const MaterialVolume& volume, const VdbLayout& layout = {});

// Refuses (jade::Error naming --resolution) a volume of s³ voxels whose
// building and writing would not fit in the memory available: 3 bytes a
// voxel held, 44 more while its levels grid and four float grids are written
// unmasked (measured before the levels grid: a 512³ run peaked at 5.9 GB).
void require_memory_for_volume(int resolution);

// Reads a file written by write_material_vdb back into the in-memory volume:
// the levels from their grid; in a format 1 file, recovered from sigma_a
// (exact whenever d_a > 0) or else from sigma_s (exact where σ_s is not
// clamped at 0) and checked against both grids.
// Throws jade::Error for a missing file, a file OpenVDB cannot read, or a .vdb
// that is not a jaderender material volume.
MaterialVolume read_material_vdb(const std::string& path);

// True when the file is a jaderender material volume (has 'jade:format'
// metadata). Throws jade::Error when the file cannot be read as OpenVDB.
bool is_material_vdb(const std::string& path);

// How a foreign .vdb's `density` grid becomes coefficients (the convention of
// Mitsuba's and Blender's volumes): σ_t = scale · density, σ_s = albedo · σ_t,
// σ_a = (1 − albedo) · σ_t, with the albedo from a Vec3f/float `color` grid
// (or Houdini's `Cd`) when the file has one, else `albedo`.
struct DensityConversion {
    float scale = 1.f;
    Spectrum albedo{0.9f};
};

// Reads a medium from a foreign .vdb whose grids sit in world space: float or
// Vec3f grids `sigma_s` and `sigma_a` (per world unit), or else `density`
// (+ `color`) converted as above. The grids are made dense over the bounding
// box of their active voxels. Their transform must be axis-aligned (a scale
// per axis and a translation) and shared. Throws jade::Error naming the file.
CoefficientGrids read_medium_vdb(const std::string& path, const DensityConversion& conversion);

}  // namespace jade

namespace jade {
// The OpenVDB library version this build reads and writes with.
const char* openvdb_version();
}  // namespace jade
