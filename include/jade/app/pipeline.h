#pragma once
// The whole method in one call (paper §4–5.4): photo + mesh → material volume
// on the mesh's cube → k_s fitted until the render's histogram brightness
// matches the photo's (fit/fit_session.h) → the fitted volume, the final
// render and the reports, written into one folder.

#include "jade/app/render_job.h"
#include "jade/fit/appearance.h"
#include "jade/fit/fit_session.h"
#include "jade/io/gltf_preview.h"
#include "jade/volume/color_match.h"
#include "jade/volume/material_volume.h"
#include "jade/volume/noise.h"
#include "jade/volume/sharpen.h"

#include <optional>
#include <string>
#include <vector>

namespace jade {

struct PipelineOptions {
    std::string photo, mask;
    double photo_span = 1.0;          // Photo::span: how many cube sides the photo spans
    std::string out_dir;              // "" = "<photo name>-jaderender" in the current folder
    std::string volume;               // a jaderender .vdb to fit instead of building one from the
                                      // photo (its d_s, d_a, density scale and noise are kept)
    // The paper's fBm, or the resolution and seed for an estimate; either
    // one's levels sharpened by noise.sharpen (volume/sharpen.h).
    NoiseParams noise;
    // Where the volume is built from the photo and fitted under --fit
    // contrast (`--sharpen auto`, the default), its first fit's outcome
    // chooses a sharpening (sharpening_for: none, kDefaultSharpen or
    // kSharperStone, by how far the fit raised the density scale); the
    // volume sharpened so is fitted from that fit's outcome and kept where
    // its fit converges (docs/design.md, "Sharpening"). Where the first fit
    // raises the density scale to its ceiling, it stops there and the stone
    // sharpened by kDefaultSharpen takes its search on; where its first rise
    // meets the stone's need short of the ceiling, likewise with
    // kSharperStone (the unsharpened stone's fit goes on from its stop only
    // where the sharper one's does not converge).
    // The first volume's levels are then noise.sharpen's, 0 by default.
    // false: noise.sharpen alone (`--sharpen β`).
    bool sharpen_from_fit = true;
    StructureMode structure = StructureMode::Photo;
    MatchMode match = MatchMode::Joint;
    OpticalParams optics;             // for a volume built from the photo
    FitOptions fit;
    RenderJob render;                 // mesh, boundary, lights, camera and the final render's settings
    bool progress = false;            // progress bars on stderr
    // Also render the fitted volume and its shading (the volume's mean
    // medium, contrast 0, same random numbers and majorant) in two halves
    // each, and compare the material with the photo, shading divided out and
    // noise taken out (fit/appearance.h, compare_material). Costs about two
    // more final renders.
    bool measure_material = false;
    // With measure_material, the goal's reach at these density scales too
    // (bench fidelity --densities; docs/design.md, "Appearance"): the fitted
    // volume's shading render (its mean medium at the fitted albedo, k_s and
    // exposure) at each, at the measuring renders' samples and seed, and
    // under it the photo's own stone's D and the least any material reaches
    // (fit/appearance.h, shading_reach). Each costs one such render.
    std::vector<double> reach_densities;
    // After a fit, check A at the final render's size (renders at both sizes
    // with a quarter of its samples, at least 64): where a channel is off by
    // more than the fit's tolerance, its k_s moves before the final render
    // (FitSession::final_brightness).
    bool final_match = true;
    // The .vdb's coefficient grids turned Z-up (Blender) instead of Y-up
    // (glTF, Houdini); they are always masked to the mesh (io/vdb_io.h).
    bool vdb_z_up = false;
    std::string vdb_color_name = "color";  // or "Cd" for Houdini
};

// The check of A at the final render's size (PipelineOptions::final_match):
// its samples per pixel and seconds, the change of A from the fitting size
// to the final one, the ΔA expected there at the fitted k_s, the k_s after
// the check (the same where every channel was within the tolerance), the
// ΔA expected at those, and the fitting renders the steps took.
struct BrightnessCheck {
    bool from_fit = false;  // A at full size from the fit's renders there (FitSession::FinalBrightness)
    // from the final render's first `spp` samples (it carried on from them
    // where k_s was kept), not from a render of the check's own
    bool from_final_render = false;
    int spp = 0, renders = 0;
    double seconds = 0.0;
    std::array<double, 3> size_change{}, delta{}, ks_before{}, ks_after{}, expected{};
    std::array<double, 3> white_share{}, noise_clipped{-1, -1, -1};  // FitSession::FinalBrightness's
    bool corrected() const { return ks_after != ks_before; }
};

// The sharper stone's fit (PipelineOptions::sharpen_from_fit), where it was
// considered: why it was not tried, or whether it was kept.
struct SharperStone {
    double first = 0.0;                 // the sharpening of the first fit's volume
    double sharper = 0.0;               // the one its outcome chose (sharpening_for; 0 = none)
    std::string why;                    // why that one (SharpeningChoice::why)
    bool tried = false;                 // the sharper stone was fitted (it asked for more than `first`)
    bool kept = false;                  // its fit converged: it is the outcome, its volume the one written
    // The first fit stopped for the sharper stone (at the density scale's
    // ceiling or first rise: stopped_for_sharper_stone) and the sharper
    // stone's fit took its search on from there.
    bool from_stop = false;
    FitOutcome other;                   // the fit not kept: the first, or the sharper stone's
    // Where the sharper stone's fit from the stop did not converge, the
    // first stone's fit went on from where it stopped and is the outcome;
    // this is that first fit up to its stop.
    std::optional<FitOutcome> stopped;
    double seconds = 0.0;               // everything after the first fit: the sharper volume, its fit, a resumption
    // Seconds from the first fit's start at which the sharper stone's fit
    // and the first stone's resumed fit began (fit.csv's seconds run on).
    double sharper_began = 0.0, resumed_began = 0.0;
};

// One fit of the pipeline's, in the order they ran: the first, the sharper
// stone's, the first stone's resumption.
struct FitLeg {
    const FitOutcome* fit = nullptr;
    double began = 0.0;                 // seconds from the first fit's start
};

struct PipelineResult {
    std::string out_dir;
    FitOutcome fit;                   // the fit of the volume written
    std::optional<SharperStone> sharper;
    std::optional<BrightnessCheck> brightness_check;
    StructureEstimate structure;      // when the structure was estimated from the photo
    bool structure_estimated = false;
    // The written volume's own slices against the photo, whatever made them
    // (measure_slice_structure; its noise is not set).
    StructureFit slices;
    // Its slices across those (normal to x and to y; measure_slice_structure_across):
    // what a side view or a vase's shoulders show.
    StructureFit slices_across;
    RenderResult final_render;
    Appearance final_look;            // the final render against the photo (fit/appearance.h)
    std::optional<MaterialAppearance> material;  // with measure_material
    std::vector<ShadingReach> reach;             // one per PipelineOptions::reach_densities, in order
    GltfPreviewMaterial preview;      // preview.glb's stand-in material (io/gltf_preview.h)
    std::vector<std::string> warnings;
    std::vector<std::string> written;
    double seconds_photo = 0, seconds_structure = 0, seconds_volume = 0, seconds_fit = 0, seconds_check = 0,
           seconds_render = 0, seconds_measure = 0, seconds_write = 0, seconds_total = 0;
};

PipelineResult run_pipeline(const PipelineOptions& options);

// Refuses a density scale for PipelineOptions::reach_densities that is not
// a positive number, as OpticalParams::validate does the volume's.
void validate_reach_densities(const std::vector<double>& densities);

// The fits `result` ran, in order (one unless a sharper stone was fitted).
std::vector<FitLeg> fit_legs(const PipelineResult& result);
// Their fitting renders, all counted.
int fit_renders(const PipelineResult& result);

// The folder a photo's results go to by default: "<stem>-jaderender".
std::string default_out_dir(const std::string& photo);

}  // namespace jade
