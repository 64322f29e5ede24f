#pragma once
// Where the directional light arrives from, inside the object (docs/design.md,
// "Light guide"): for every cell of a coarse grid over the object and for
// each specular chain the light estimators follow (render/light_estimator.h:
// straight in after the refraction, after one internal reflection too, or
// after a reflection off the outside of another part of the object before
// the refraction), a histogram of the directions toward the light of the
// light that reaches the cell, over equal-area bins (core/sphere_bins.h).
// It is built before a render by tracing the light's disc into the object
// (light traced into a directional grid to guide the paths, as Jensen 1995
// guided them by the photon map, "Importance driven path tracing using the
// photon map").
//
// The light estimators draw directions from it (light_estimators/guided.h):
// a direction toward where a chain's light comes from leaves through the
// face that light came in by (after the reflection inside, for the second
// chain; then on to the part that mirrored it, for the third) and meets the
// disc, whichever face that is. The other estimators aim at
// one surface point only. The histogram is a density known for every
// direction, so the estimators' samples and the paths that meet the light
// by themselves are weighed against each other by MIS.
//
// A cell's histogram averages the directions over the whole cell, and
// under a curved surface the light's direction changes across a cell by as
// much as a small disc's width. So for the light straight in and the light
// mirrored off the outside, each cell also fits a lobe to its rays: the
// direction as an affine function of the position in the cell, and an
// elliptic cone about it as wide as the rays' spread about that function
// (core/direction_fit.h). Where a cell has one, half of the directions are
// drawn from the lobe at the vertex, half from the histogram, and the
// density is the mixture's.
//
// Each stretch of light deposits its length in the cell (a track-length
// estimate of the light's fluence there) times its weight through the
// boundary and e^(−σ̄ s) after s inside, σ̄ the smallest channel's
// majorant: directions whose light arrives through much medium are drawn
// less often, as they contribute less. A cell's histogram is mixed with its
// 3×3×3 neighbourhood's, so bins and cells that few of the traced rays
// reached are not left empty. Only the cells the light reaches, and their
// neighbours, hold histograms: memory follows the lit part of the object,
// not its bounding box.

#include "jade/core/bounds.h"
#include "jade/core/direction_fit.h"
#include "jade/core/sphere_bins.h"
#include "jade/render/light_estimator.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace jade {

struct Scene;

struct LightGuideSettings {
    int cells = 24;                      // cells along the object's longest side
    std::uint32_t photons = 1u << 18;    // rays traced from the light's disc
};

// The rays a guide traces for a render of `camera_samples` samples in all
// (pixels × samples per pixel): one per 64, at least 2^18 and at most 2^20,
// but at most one per 4 camera samples (and at least 2^12), so that the
// guide is a small share of any render's time and a long render has a finer
// one (docs/design.md, "Light guide").
std::uint32_t light_guide_photons(double camera_samples);

class LightGuide {
public:
    // The chains through the boundary it knows: Refraction (0),
    // ReflectionRefraction (1) and RefractionReflection (2); −1 for None.
    static constexpr int kChains = 3;
    static int chain_index(SpecularChain chain);

    // Nothing guided (every histogram() is −1).
    LightGuide() = default;
    // The guide of scene.light (a disc, on) behind scene.boundary: photon i
    // draws its numbers from SampleStream(seed, i, ·), and the histograms
    // are summed in fixed point, so the guide does not depend on the
    // number of threads.
    LightGuide(const Scene& scene, std::uint64_t seed, const LightGuideSettings& settings = {});

    bool empty() const { return cdf_.empty(); }
    // The histogram of `chain` in the cell holding p, or −1 (outside the
    // grid, or no light of that chain reached it).
    int histogram(const glm::vec3& p, SpecularChain chain) const;
    // The share of the directions a cell with a lobe draws from it. On the
    // demo at 20° (256², 30 s, three seed pairs) 0.5 and 0.7 did alike.
    static constexpr float kLobeShare = 0.5f;
    // The guide at a vertex: histogram h (≥ 0) of the vertex's cell and the
    // cone of its lobe there, if it has one. An estimator that draws a
    // direction and then asks its density finds the cone once.
    struct Site {
        int histogram = -1;
        std::optional<EllipticCone> lobe;
    };
    Site site(int h, const glm::vec3& p) const { return {h, lobe(h, p)}; }
    // A direction drawn at the site: from the lobe (kLobeShare of them,
    // where there is one) or from the histogram's bins; u's in [0, 1).
    glm::vec3 sample(const Site& site, float u1, float u2, float u3) const;
    // Its density in solid angle.
    float pdf(const Site& site, const glm::vec3& w) const;
    // The bins alone: a direction drawn from them, and their density.
    glm::vec3 sample_bins(int h, float u1, float u2, float u3) const;
    float bins_pdf(int h, const glm::vec3& w) const;
    // The cone of histogram h's lobe at p (in h's cell), or none.
    std::optional<EllipticCone> lobe(int h, const glm::vec3& p) const;
    // Histogram h's share of the light its cell receives by all chains.
    float share(int h) const { return share_[std::size_t(h)]; }
    const SphereBins& bins() const { return bins_; }
    std::size_t histograms() const { return cdf_.size() / std::size_t(bins_.count()); }
    std::size_t memory_bytes() const;

private:
    SphereBins bins_;
    glm::vec3 origin_{0.f};
    float cell_size_ = 1.f;
    std::array<int, 3> dims_{0, 0, 0};
    std::vector<std::int32_t> slot_;  // per grid cell and chain: its histogram, or −1
    std::vector<float> cdf_;          // per histogram, bins_.count() cumulative shares (last 1)
    // Per histogram, the cumulative share at the end of each row of bins
    // (bins_.n values, contiguous): sample() searches these first and then
    // one row, a few cache lines instead of a search over the whole cdf.
    std::vector<float> row_ends_;
    std::vector<float> share_;        // per histogram, share()
    std::vector<std::optional<DirectionLobe>> lobes_;  // per histogram, its cell's lobe (light_guide.cpp, has_lobe)
};

}  // namespace jade
