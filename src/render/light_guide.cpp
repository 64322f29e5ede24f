#include "jade/render/light_guide.h"

#include "jade/core/direction_fit.h"
#include "jade/core/random.h"
#include "jade/core/sampling.h"
#include "jade/core/spectrum.h"
#include "jade/render/dielectric.h"
#include "jade/render/scene.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace jade {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// A traced ray is followed until its weight (boundary and e^(−σ̄ s))
// falls below this: what is left would hardly move a histogram.
constexpr float kSmallestWeight = 1e-4f;
// Deposits are summed as integers in units of 2^-32 of a whole cell's
// length at full weight: integer sums do not depend on their order.
constexpr double kFixedUnit = 4294967296.0;
// The share of a cell's histogram taken from the mean of its 3×3×3
// neighbourhood (docs/design.md, "Light guide"). A histogram estimated from
// the light's rays alone is empty where few of them passed: then a path
// that meets the light in such a direction has no estimator's density to be
// weighed against, and its full weight is the rare sample that holds much
// of the image's variance. Mixing in the neighbours' light fills those
// gaps. On the demo at equal time (256², 128 spp, three seed pairs) 0.3
// lowered the relative MSE 8 %, 0.6 as much; smoothing over the
// neighbouring bins of a direction as well added nothing.
constexpr float kNeighbourShare = 0.3f;
// Photon i draws from SampleStream(seed, i, kStream).
constexpr std::uint64_t kStream = 0x4c4947ull;
// The sums of a cell's lobe (core/direction_fit.h) are integers in units
// of 2^-36, added as two's complement in unsigned words: a sum of
// products of weights below 2 and positions within half a cell stays far
// below 2^63 units for millions of stretches.
constexpr double kLobeUnit = 68719476736.0;

// Whether a chain's histograms get a lobe: the light straight in and the
// light mirrored off the outside, whose directions change fastest across a
// cell (docs/design.md, "The cells' lobes").
bool has_lobe(int chain) {
    return chain == LightGuide::chain_index(SpecularChain::Refraction) ||
           chain == LightGuide::chain_index(SpecularChain::RefractionReflection);
}

// The largest float below 1: a number rescaled into [0, 1) stays there.
constexpr float kOneBelow = 0x1.fffffep-1f;

// Where p lies in its cell of the grid, in cell lengths from the cell's
// centre (each coordinate in [−0.5, 0.5)): the lobes' positions.
glm::vec3 cell_offset(const glm::vec3& p, const glm::vec3& origin, float cell_size) {
    const glm::vec3 q = (p - origin) / cell_size;
    return q - glm::floor(q) - glm::vec3(0.5f);
}

// The cell of a grid (dims cells of side cell_size from origin) holding p,
// x fastest; −1 outside.
long grid_cell(const glm::vec3& p, const glm::vec3& origin, float cell_size, const std::array<int, 3>& dims) {
    const glm::vec3 q = (p - origin) / cell_size;
    long index = 0;
    for (int k = 2; k >= 0; --k) {
        const float f = std::floor(q[k]);
        if (!(f >= 0.f && f < float(dims[std::size_t(k)]))) return -1;
        index = index * dims[std::size_t(k)] + long(f);
    }
    return index;
}

// Per histogram of the grid, its sums (one per bin), allocated when light
// first reaches it: memory for the cells the light reaches, not the grid.
class LazySums {
public:
    LazySums(std::size_t histograms, std::size_t bins) : blocks_(histograms), bins_(bins) {}
    LazySums(const LazySums&) = delete;
    LazySums& operator=(const LazySums&) = delete;
    ~LazySums() {
        for (auto& b : blocks_) delete[] b.load();
    }

    void add(std::size_t h, std::size_t bin, std::uint64_t q) {
        std::atomic<std::uint64_t>* block = blocks_[h].load(std::memory_order_acquire);
        if (!block) {
            auto* fresh = new std::atomic<std::uint64_t>[bins_]();
            if (blocks_[h].compare_exchange_strong(block, fresh, std::memory_order_acq_rel))
                block = fresh;
            else
                delete[] fresh;  // another thread's came first: `block` now holds it
        }
        block[bin].fetch_add(q, std::memory_order_relaxed);
    }
    // Histogram h's sums, or null where no light reached it.
    const std::atomic<std::uint64_t>* sums(std::size_t h) const { return blocks_[h].load(); }

private:
    std::vector<std::atomic<std::atomic<std::uint64_t>*>> blocks_;
    std::size_t bins_;
};

// The grid the deposits are summed in, as the traced rays see it.
struct Deposits {
    const SphereBins& bins;
    glm::vec3 origin;
    float cell_size;
    std::array<int, 3> dims;
    float sigma;  // σ̄
    LazySums& sums;
    LazySums& lobe_sums;  // DirectionSums::kCount per histogram, of the chains with lobes

    // The stretch o + t·d, t ∈ [0, length), of light of weight `weight`
    // that has come `travelled` through the medium, in the histograms of
    // chain index `chain` (LightGuide::chain_index); false once what is
    // left of it is below kSmallestWeight.
    bool add(const glm::vec3& o, const glm::vec3& d, float length, float weight, int chain,
             float& travelled) const {
        const int bin = bins.index(-d);  // toward where the light comes from
        const float step = 0.5f * cell_size;
        // Consecutive steps in one cell are summed before they are stored:
        // one store per cell crossed, not per step.
        long cell = -1;
        std::uint64_t pending = 0;
        StretchSums stretch;  // the lobe's sums of the steps in `cell`
        const bool lobe = has_lobe(chain);
        bool lit = true;
        for (float s = 0.f; s < length; s += step) {
            const float ds = std::min(step, length - s);
            const float a = weight * std::exp(-sigma * (travelled + s + 0.5f * ds));
            if (a < kSmallestWeight) {
                lit = false;
                break;
            }
            const glm::vec3 x = o + (s + 0.5f * ds) * d;
            const long c = grid_cell(x, origin, cell_size, dims);
            if (c != cell) {
                store(cell, chain, bin, pending);
                if (lobe) store_lobe(cell, chain, -d, stretch);
                cell = c;
                pending = 0;
                stretch = StretchSums{};
            }
            if (c < 0) continue;
            const double q = double(a) * double(ds / cell_size);
            pending += std::uint64_t(q * kFixedUnit);
            if (lobe) stretch.add(q, glm::dvec3(cell_offset(x, origin, cell_size)));
        }
        store(cell, chain, bin, pending);
        if (lobe) store_lobe(cell, chain, -d, stretch);
        travelled += length;
        return lit && weight * std::exp(-sigma * travelled) >= kSmallestWeight;
    }

    // q units of light in bin `bin` of cell c's histogram of `chain`.
    void store(long c, int chain, int bin, std::uint64_t q) const {
        if (c >= 0 && q > 0) sums.add(std::size_t(c) * LightGuide::kChains + std::size_t(chain), std::size_t(bin), q);
    }
    // A stretch's part in cell c, of direction w toward the light, in the
    // sums of that cell's lobe.
    void store_lobe(long c, int chain, const glm::vec3& w, const StretchSums& stretch) const {
        if (c < 0 || !(stretch.q > 0.0)) return;
        DirectionSums part;
        part.add(stretch, w);
        const std::size_t h = std::size_t(c) * LightGuide::kChains + std::size_t(chain);
        for (int i = 0; i < DirectionSums::kCount; ++i)
            lobe_sums.add(h, std::size_t(i), std::uint64_t(std::llround(part.v[std::size_t(i)] * kLobeUnit)));
    }
};

// The light's ray through a point of the disc about the object's bounding
// sphere (centre c, radius r), uniform over the disc and over the light's
// cone of directions, as irradiance falls; false when it misses.
bool light_ray(const Scene& scene, const glm::vec3& c, float r, SampleStream& rng, glm::vec3& o,
               glm::vec3& d, std::optional<SurfaceHit>& hit) {
    float pdf = 0.f;
    const float u1 = rng.uniform(), u2 = rng.uniform();
    const glm::vec3 w = scene.light.disc().sample(u1, u2, pdf);  // toward the light
    glm::vec3 b1, b2;
    orthonormal_basis(w, b1, b2);
    const float rho = r * std::sqrt(rng.uniform()), phi = 2.f * kPi * rng.uniform();
    o = c + 2.f * r * w + rho * (std::cos(phi) * b1 + std::sin(phi) * b2);
    d = -w;
    hit = scene.boundary->intersect(o, d, 0.f, kInfinity);
    return hit && glm::dot(d, hit->geometric_normal) < 0.f;
}

// Light of weight `weight` refracted in at surface point y (geometric
// normal ng) along d: straight on inside (chain 0), and once reflected at
// the surface (chain 1).
void trace_inside(const Scene& scene, const glm::vec3& y, const glm::vec3& ng, glm::vec3 d, float weight,
                  const Deposits& deposits) {
    Scene::Spawn spawn = scene.spawn_inside(y, ng, d);
    float travelled = 0.f;
    for (int reflections = 0;; ++reflections) {
        const auto hit = scene.boundary->intersect(spawn.origin, d, spawn.query_from, kInfinity);
        const SpecularChain chain = reflections == 0 ? SpecularChain::Refraction : SpecularChain::ReflectionRefraction;
        if (!hit || !deposits.add(spawn.origin, d, hit->t, weight, LightGuide::chain_index(chain), travelled))
            return;
        if (reflections == 1) return;
        const glm::vec3& n_g = hit->geometric_normal;
        if (!(glm::dot(d, n_g) > 0.f)) return;  // not leaving: a crack or a sliver
        const glm::vec3 p = spawn.origin + hit->t * d;
        const glm::vec3 n = interface_normal(*hit, d, false);
        weight *= 1.f - boundary_transmission(scene.interface, d, n, false).weight;
        const glm::vec3 reflected = reflect(d, n);
        if (!(weight > 0.f) || !on_sampled_side(d, reflected, n_g, true)) return;
        d = reflected;
        spawn = scene.spawn_inside(p, n_g, d);
    }
}

// Light of weight `weight` reflected off the outside at y along m: where
// it meets another part of the object, refracted in and straight on
// (chain 2).
void trace_mirrored(const Scene& scene, const glm::vec3& y, const glm::vec3& ng, const glm::vec3& m,
                    float weight, const Deposits& deposits) {
    if (!(glm::dot(m, ng) > 0.f) || scene.boundary->convex()) return;  // nothing to meet again
    const auto hit = scene.boundary->intersect(scene.offset(y, ng, m), m, 0.f, kInfinity);
    if (!hit || !(glm::dot(m, hit->geometric_normal) < 0.f)) return;
    const BoundaryTransmission in =
        boundary_transmission(scene.interface, m, interface_normal(*hit, m, true), true);
    weight *= in.weight;
    if (!(weight > 0.f)) return;
    const glm::vec3 p = scene.offset(y, ng, m) + hit->t * m;
    const Scene::Spawn spawn = scene.spawn_inside(p, hit->geometric_normal, in.direction);
    const auto inside = scene.boundary->intersect(spawn.origin, in.direction, spawn.query_from, kInfinity);
    float travelled = 0.f;
    if (inside)
        deposits.add(spawn.origin, in.direction, inside->t, weight,
                     LightGuide::chain_index(SpecularChain::RefractionReflection), travelled);
}

// The histograms of the cells within one cell (3×3×3) of one the light
// reached, of the same chain: those the neighbourhood mean gives light.
// Dilated one axis at a time.
std::vector<std::uint8_t> near_light(const LazySums& sums, const std::array<int, 3>& dims) {
    const std::size_t cells = std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]);
    constexpr std::size_t k = LightGuide::kChains;
    std::vector<std::uint8_t> near(cells * k), next(cells * k);
    for (std::size_t h = 0; h < near.size(); ++h) near[h] = sums.sums(h) != nullptr;
    std::size_t stride = 1;
    for (std::size_t axis = 0; axis < 3; stride *= std::size_t(dims[axis]), ++axis) {
        const std::size_t n = std::size_t(dims[axis]);
        for (std::size_t c = 0; c < cells; ++c) {
            const std::size_t i = (c / stride) % n;
            for (std::size_t chain = 0; chain < k; ++chain) {
                std::uint8_t v = near[c * k + chain];
                if (i > 0) v |= near[(c - stride) * k + chain];
                if (i + 1 < n) v |= near[(c + stride) * k + chain];
                next[c * k + chain] = v;
            }
        }
        near.swap(next);
    }
    return near;
}

// The deposits (in cell lengths, `block` values per histogram; histogram
// h at slot[h], or nowhere) averaged over each cell's 3×3×3 neighbourhood,
// cells beyond the grid counting as dark. Filtered in place one axis at a
// time, so it needs no more than the one copy. A histogram without a slot
// is dark, and so is every partial sum over its neighbourhood: the light
// reached no cell within one of it.
std::vector<float> neighbourhood_means(std::vector<float> v, const std::vector<std::int32_t>& slot,
                                       const std::array<int, 3>& dims, std::size_t block) {
    const std::size_t cells = std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]);
    constexpr std::size_t k = LightGuide::kChains;
    const auto at = [&](std::size_t c, std::size_t chain) {
        const std::int32_t s = slot[c * k + chain];
        return s < 0 ? nullptr : &v[std::size_t(s) * block];
    };
    std::vector<float> before(block), here(block);
    std::size_t stride = 1;
    for (std::size_t axis = 0; axis < 3; stride *= std::size_t(dims[axis]), ++axis) {
        const std::size_t n = std::size_t(dims[axis]);
        for (std::size_t first = 0; first < cells; ++first) {
            if ((first / stride) % n != 0) continue;  // not the first cell of a line along the axis
            for (std::size_t chain = 0; chain < k; ++chain) {
                std::fill(before.begin(), before.end(), 0.f);
                for (std::size_t i = 0; i < n; ++i) {
                    float* cell = at(first + i * stride, chain);
                    if (!cell) {
                        std::fill(before.begin(), before.end(), 0.f);
                        continue;
                    }
                    const float* after = i + 1 < n ? at(first + (i + 1) * stride, chain) : nullptr;
                    std::copy(cell, cell + block, here.begin());
                    for (std::size_t x = 0; x < block; ++x)
                        cell[x] = (before[x] + here[x] + (after ? after[x] : 0.f)) / 3.f;
                    before.swap(here);
                }
            }
        }
    }
    return v;
}

// One ray from the light where it meets the object: its reflection off the
// outside and its refraction in.
void trace_photon(const Scene& scene, const glm::vec3& c, float r, SampleStream& rng,
                  const Deposits& deposits) {
    glm::vec3 o, d;
    std::optional<SurfaceHit> hit;
    if (!light_ray(scene, c, r, rng, o, d, hit)) return;
    const glm::vec3 y = o + hit->t * d;
    const glm::vec3& ng = hit->geometric_normal;
    const glm::vec3 n = interface_normal(*hit, d, true);
    const BoundaryTransmission in = boundary_transmission(scene.interface, d, n, true);
    if (in.weight < 1.f) trace_mirrored(scene, y, ng, reflect(d, glm::dot(d, n) < 0.f ? n : -n), 1.f - in.weight,
                                        deposits);
    if (in.weight > 0.f && on_sampled_side(d, in.direction, ng, false))
        trace_inside(scene, y, ng, in.direction, in.weight, deposits);
}

// The guide's histograms from the light in each bin of those that have a
// place (`place`, −1 for none; nb bins each): each bin's light is its own
// (`own`) mixed with its neighbourhood's (`light`, where the cumulative
// distributions are then built in place). A histogram with light gets its
// slot (in the order of the grid), its share of its cell's light and its
// cumulative distribution over the bins.
struct Histograms {
    std::vector<std::int32_t> slot;
    std::vector<float> share, cdf;
};

Histograms normalised_histograms(const std::vector<std::int32_t>& place, const std::vector<float>& own,
                                 std::vector<float> light, std::size_t nb) {
    constexpr std::size_t k = LightGuide::kChains;
    Histograms out;
    out.slot.assign(place.size(), -1);
    std::size_t made = 0;
    for (std::size_t c = 0; c < place.size() / k; ++c) {
        double totals[k] = {}, cell_total = 0.0;
        for (std::size_t chain = 0; chain < k; ++chain) {
            const std::int32_t at = place[c * k + chain];
            if (at < 0) continue;
            for (std::size_t i = std::size_t(at) * nb; i < std::size_t(at + 1) * nb; ++i) {
                light[i] = float((1.0 - kNeighbourShare) * double(own[i]) + kNeighbourShare * double(light[i]));
                totals[chain] += light[i];
            }
            cell_total += totals[chain];
        }
        // Written at `made`, never after where it is read from.
        for (std::size_t chain = 0; chain < k; ++chain) {
            if (!(totals[chain] > 0.0)) continue;
            const float* from = &light[std::size_t(place[c * k + chain]) * nb];
            float* to = &light[made * nb];
            out.slot[c * k + chain] = std::int32_t(made++);
            out.share.push_back(float(totals[chain] / cell_total));
            double running = 0.0;
            for (std::size_t b = 0; b < nb; ++b) {
                running += from[b];
                to[b] = float(running / totals[chain]);
            }
            to[nb - 1] = 1.f;
        }
    }
    light.resize(made * nb);
    out.cdf = std::move(light);
    return out;
}

// Every photon of the guide into `deposits` (photon i from
// SampleStream(seed, i, kStream)).
void trace_photons(const Scene& scene, std::uint64_t seed, std::uint32_t photons, const Deposits& deposits) {
    const Bounds3 box = scene.boundary->bounds();
    const glm::vec3 centre = 0.5f * (box.min + box.max);
    const float radius = 0.5f * glm::length(box.extent()) * 1.01f;
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, photons, 1024),
                      [&](const tbb::blocked_range<std::uint32_t>& range) {
                          for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
                              SampleStream rng(seed, i, kStream);
                              trace_photon(scene, centre, radius, rng, deposits);
                          }
                      });
}

// The lobe of every histogram whose sums hold light and fit one
// (core/direction_fit.h), with its index in the grid's histograms.
std::vector<std::pair<std::size_t, DirectionLobe>> fitted_lobes(const LazySums& lobe_sums, std::size_t histograms) {
    std::vector<std::pair<std::size_t, DirectionLobe>> lobes;
    for (std::size_t h = 0; h < histograms; ++h) {
        const std::atomic<std::uint64_t>* from = lobe_sums.sums(h);
        if (!from) continue;
        DirectionSums sums;
        for (int i = 0; i < DirectionSums::kCount; ++i)
            sums.v[std::size_t(i)] = double(std::int64_t(from[i].load())) / kLobeUnit;
        if (const std::optional<DirectionLobe> lobe = fit_direction_lobe(sums)) lobes.emplace_back(h, *lobe);
    }
    return lobes;
}

}  // namespace

std::uint32_t light_guide_photons(double camera_samples) {
    constexpr double kSamplesPerRay = 64.0, kFewest = 1u << 18, kMost = 1u << 20;
    // A guide ray costs about 0.6 of a camera sample (both are random walks;
    // a camera path also estimates the light at every vertex): at most one
    // ray per 4 camera samples keeps a small render's guide under a sixth of
    // its time, where 2^18 rays took four fifths of a 24 × 20 image of 37
    // spp. 2^12 rays at the least, for renders of a few thousand samples.
    constexpr double kSamplesPerRayAtMost = 4.0, kFloor = 1u << 12;
    const double fewest = std::clamp(camera_samples / kSamplesPerRayAtMost, kFloor, kFewest);
    return std::uint32_t(std::clamp(camera_samples / kSamplesPerRay, fewest, kMost));
}

LightGuide::LightGuide(const Scene& scene, std::uint64_t seed, const LightGuideSettings& settings) {
    if (!scene.boundary || !scene.medium || !scene.light.on() || scene.light.is_delta() ||
        scene.interface.mode == BoundaryMode::None || settings.cells < 1)
        return;
    const Bounds3 box = scene.boundary->bounds();
    const glm::vec3 extent = box.extent();
    const float longest = max_component(extent);
    if (!(longest > 0.f)) return;
    cell_size_ = longest / float(settings.cells);
    origin_ = box.min;
    for (int k = 0; k < 3; ++k)
        dims_[std::size_t(k)] = std::max(1, int(std::ceil(extent[k] / cell_size_)));
    const std::size_t cells = std::size_t(dims_[0]) * std::size_t(dims_[1]) * std::size_t(dims_[2]);
    const std::size_t nb = std::size_t(bins_.count());
    // The deposits, then (in cell lengths) those of the histograms the light
    // reached and of their neighbours, each at its place in `own`.
    std::vector<std::int32_t> slot(cells * kChains, -1);
    std::vector<float> own;
    std::vector<std::pair<std::size_t, DirectionLobe>> lobes;  // by histogram of the grid, in its order
    {
        LazySums sums(slot.size(), nb), lobe_sums(slot.size(), DirectionSums::kCount);
        const Deposits deposits{bins_,  origin_, cell_size_, dims_, min_component(scene.medium->majorant()),
                                sums,   lobe_sums};
        trace_photons(scene, seed, settings.photons, deposits);
        lobes = fitted_lobes(lobe_sums, slot.size());
        const std::vector<std::uint8_t> near = near_light(sums, dims_);
        std::size_t places = 0;
        for (std::size_t h = 0; h < slot.size(); ++h)
            if (near[h]) slot[h] = std::int32_t(places++);
        if (places == 0) return;
        own.assign(places * nb, 0.f);
        for (std::size_t h = 0; h < slot.size(); ++h)
            if (const std::atomic<std::uint64_t>* from = sums.sums(h))
                for (std::size_t b = 0; b < nb; ++b)
                    own[std::size_t(slot[h]) * nb + b] = float(double(from[b].load()) / kFixedUnit);
    }
    std::vector<float> neighbours = neighbourhood_means(own, slot, dims_, nb);
    Histograms made = normalised_histograms(slot, own, std::move(neighbours), nb);
    lobes_.resize(made.share.size());
    for (auto& [h, lobe] : lobes)
        if (made.slot[h] >= 0) lobes_[std::size_t(made.slot[h])] = lobe;
    slot_ = std::move(made.slot);
    share_ = std::move(made.share);
    cdf_ = std::move(made.cdf);
    const std::size_t n = std::size_t(bins_.n);
    row_ends_.resize(cdf_.size() / n);
    for (std::size_t r = 0; r < row_ends_.size(); ++r) row_ends_[r] = cdf_[r * n + n - 1];
}

int LightGuide::histogram(const glm::vec3& p, SpecularChain chain) const {
    const int k = chain_index(chain);
    if (slot_.empty() || k < 0) return -1;
    const long c = grid_cell(p, origin_, cell_size_, dims_);
    return c < 0 ? -1 : slot_[std::size_t(c) * kChains + std::size_t(k)];
}

int LightGuide::chain_index(SpecularChain chain) {
    switch (chain) {
    case SpecularChain::Refraction: return 0;
    case SpecularChain::ReflectionRefraction: return 1;
    case SpecularChain::RefractionReflection: return 2;
    case SpecularChain::None: break;
    }
    return -1;
}

// The first bin whose cumulative share exceeds u1, as one search over the
// whole cdf would find it: the rows before the one found end at or below
// u1, and the row found ends above it.
std::optional<EllipticCone> LightGuide::lobe(int h, const glm::vec3& p) const {
    const std::optional<DirectionLobe>& lobe = lobes_[std::size_t(h)];
    if (!lobe) return std::nullopt;
    return lobe->cone(cell_offset(p, origin_, cell_size_));
}

// From the lobe with probability kLobeShare (u1 below it, rescaled),
// otherwise from the bins.
glm::vec3 LightGuide::sample(const Site& site, float u1, float u2, float u3) const {
    if (site.lobe) {
        if (u1 < kLobeShare) return site.lobe->sample(u1 / kLobeShare, u2);
        u1 = std::min((u1 - kLobeShare) / (1.f - kLobeShare), kOneBelow);
    }
    return sample_bins(site.histogram, u1, u2, u3);
}

float LightGuide::pdf(const Site& site, const glm::vec3& w) const {
    const float bins = bins_pdf(site.histogram, w);
    return site.lobe ? (1.f - kLobeShare) * bins + kLobeShare * site.lobe->pdf(w) : bins;
}

glm::vec3 LightGuide::sample_bins(int h, float u1, float u2, float u3) const {
    const std::ptrdiff_t n = bins_.n;
    const auto rows = row_ends_.begin() + std::ptrdiff_t(h) * n;
    const std::ptrdiff_t row = std::min<std::ptrdiff_t>(std::upper_bound(rows, rows + n, u1) - rows, n - 1);
    const auto first = cdf_.begin() + std::ptrdiff_t(h) * bins_.count() + row * n;
    const std::ptrdiff_t column = std::min<std::ptrdiff_t>(std::upper_bound(first, first + n, u1) - first, n - 1);
    return bins_.direction(int(row * n + column), u2, u3);
}

float LightGuide::bins_pdf(int h, const glm::vec3& w) const {
    const std::size_t first = std::size_t(h) * std::size_t(bins_.count());
    const int b = bins_.index(w);
    const float share = cdf_[first + std::size_t(b)] - (b > 0 ? cdf_[first + std::size_t(b) - 1] : 0.f);
    return share / bins_.solid_angle();
}

std::size_t LightGuide::memory_bytes() const {
    return slot_.size() * sizeof(std::int32_t) + (cdf_.size() + row_ends_.size() + share_.size()) * sizeof(float) +
           lobes_.size() * sizeof(std::optional<DirectionLobe>);
}

}  // namespace jade
