#include "jade/volume/noise.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/random.h"

#include <tbb/parallel_for.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace jade {

int NoiseParams::octave_count() const {
    if (octaves > 0) return octaves;
    int n = 0;
    while ((2 << n) <= resolution) ++n;  // floor(log2(s))
    return n < 1 ? 1 : n;
}

NoiseParams magnified(const NoiseParams& p, double m) {
    if (m == 1.0) return p;
    NoiseParams q = p;
    q.frequency = p.frequency / m;
    q.vein_frequency = p.vein_frequency / m;
    q.bands = p.bands / m;
    q.warp = p.warp * m;
    q.octaves = std::clamp(p.octave_count() + int(std::lround(std::log2(m))), 1, 30);
    return q;
}

std::string NoiseParams::family_suffix() const {
    char buf[96];
    std::string s;
    if (exemplar) {
        // The noise's own families do not apply: only the sweep and the sharpening.
        std::snprintf(buf, sizeof buf, ", the photo swept in depth (wander %.3g)", exemplar_wander);
        s += buf;
    } else {
        if (layers) s += ", layers";
        if (bands > 0.0 && fold != 1.0) {
            std::snprintf(buf, sizeof buf, ", fold %.2f", fold);
            s += buf;
        }
        if (veins) {
            std::snprintf(buf, sizeof buf, ", veins (frequency %.2f, width %.4g)", vein_frequency, vein_width);
            s += buf;
        }
    }
    if (sharpen > 0.0) {
        std::snprintf(buf, sizeof buf, ", sharpened (%.3g over %.3g voxels)", sharpen, sharpen_radius);
        s += buf;
    }
    return s;
}

// A sixteenth of a cycle per side: the estimate's least frequencies (half a
// cycle per photo, one per photo for the veins) magnified by the widest
// photo span, 8 (Photo::span).
constexpr double kMinFrequency = 0.0625;

void NoiseParams::validate() const {
    if (resolution < 2 || resolution > 1024)
        throw Error("--resolution must be between 2 and 1024 voxels, got " +
                    std::to_string(resolution));
    if (octaves < 0 || octaves > 30)
        throw Error("--octaves must be between 1 and 30 (0 = log2 of the resolution), got " +
                    std::to_string(octaves));
    if (!(k > 0.0 && k < 1.0))
        throw Error("--k must lie strictly between 0 and 1, got " + std::to_string(k));
    if (!(frequency >= kMinFrequency && frequency <= 64.0))
        throw Error("--frequency must be between 0.0625 and 64 cycles per side, got " +
                    std::to_string(frequency));
    if (!(stretch >= 1.0 && stretch <= 64.0))
        throw Error("--stretch must be between 1 and 64, got " + std::to_string(stretch));
    if (!std::isfinite(angle)) throw Error("--angle must be a finite number of degrees");
    if (!(bands >= 0.0 && bands <= 256.0))
        throw Error("--bands must be between 0 (none) and 256 per side, got " + std::to_string(bands));
    if (!(warp >= 0.0 && warp <= 256.0))
        throw Error("--warp must be between 0 and 256 cube sides, got " + std::to_string(warp));
    if (!(fold >= 0.0 && fold <= 1.0))
        throw Error("--fold must be between 0 (every layer folds alike) and 1 (isotropic warp), got " +
                    std::to_string(fold));
    if (!(vein_frequency >= kMinFrequency && vein_frequency <= 64.0))
        throw Error("--vein-frequency must be between 0.0625 and 64 cycles per side, got " +
                    std::to_string(vein_frequency));
    if (!(vein_width > 0.0 && vein_width <= 0.5))
        throw Error("--vein-width must lie above 0 and at most 0.5, got " + std::to_string(vein_width));
    if (!(sharpen >= 0.0 && sharpen <= 16.0))
        throw Error("--sharpen must be between 0 (none) and 16, got " + std::to_string(sharpen));
    if (!(sharpen_radius >= 0.25 && sharpen_radius <= 16.0))
        throw Error("--sharpen-radius must be between 0.25 and 16 voxels, got " + std::to_string(sharpen_radius));
    if (!(exemplar_wander >= 0.0 && exemplar_wander <= 8.0))
        throw Error("--exemplar-wander must be between 0 and 8 cube sides, got " + std::to_string(exemplar_wander));
    if (layers && !(bands > 0.0))
        throw Error("--layers needs --bands above 0, the layers per cube side of the profile's first octave "
                    "(with --structure photo the estimate searches layers by itself)");
}

namespace {

// Kernel radius squared. 0.5 is the largest radius for which a corner's
// influence vanishes before the point leaves the corner's simplices, so the
// noise is continuous (Gustavson's 0.6 leaves small seams).
constexpr double kRadius2 = 0.5;

// Scale making |noise| <= 1 provably: each of the four corners contributes at
// most |g| * max_r r (R^2 - r^2)^4 with |g| = sqrt(2), reached at r^2 = R^2/9.
// For R^2 = 1/2 that is sqrt(2) * sqrt(1/18) * (4/9)^4 = 256/19683 per corner.
constexpr double kNoiseScale = 19683.0 / (4.0 * 256.0);
static_assert(kRadius2 == 0.5, "kNoiseScale is derived for R^2 = 1/2");

// The twelve gradients: midpoints of a cube's edges.
// Doubles, not ints: the products with a corner's offset are the same
// (exact ±1 and 0), without converting each of the twelve per call.
constexpr double kGrad[12][3] = {{1, 1, 0},  {-1, 1, 0},  {1, -1, 0}, {-1, -1, 0},
                                 {1, 0, 1},  {-1, 0, 1},  {1, 0, -1}, {-1, 0, -1},
                                 {0, 1, 1},  {0, -1, 1},  {0, 1, -1}, {0, -1, -1}};

// The layers' warp is the paper's fBm (§4.1, k = 1/2): smooth folds.
constexpr double kLayerWarpRatio = 0.5;
constexpr int kLayerWarpOctaves = 3;
// Added to the profile offsets' index before hashing, apart from the warp's.
constexpr std::uint64_t kProfileSalt = 0x9e3779b9ull;
// The veins' fBm: the paper's amplitude ratio, so their curves are smooth at
// the large scale and wander at the small, with octaves up to a quarter of a
// cycle per voxel (the finest sampled at four voxels a cycle, well inside
// the grid's Nyquist limit) and at most six. Its offsets are salted apart
// from the others'.
constexpr double kVeinRatio = 0.5;
constexpr int kVeinOctaves = 6;
constexpr std::uint64_t kVeinSalt = 0x7f4a7c15ull;

inline int fast_floor(double x) {
    const int i = int(x);
    return x < i ? i - 1 : i;
}

// A corner's contribution: (R^2 - r^2)^4 (g . d), zero beyond the radius.
// Branch-free: which corners are in range is random, so a branch would be
// mispredicted about half the time.
inline double corner(int gi, double x, double y, double z) {
    double t = std::max(kRadius2 - x * x - y * y - z * z, 0.0);
    t *= t;
    return t * t * (kGrad[gi][0] * x + kGrad[gi][1] * y + kGrad[gi][2] * z);
}

}  // namespace

SimplexNoise::SimplexNoise(std::uint32_t seed) {
    for (int i = 0; i < 256; ++i) perm_[i] = std::uint8_t(i);
    SplitMix64 rng(0x6A6164655F6E6F69ull ^ seed);  // Fisher-Yates shuffle
    for (int i = 255; i > 0; --i) {
        const int j = int(rng.below(std::uint64_t(i) + 1));
        std::swap(perm_[i], perm_[j]);
    }
    for (int i = 0; i < 256; ++i) perm_[256 + i] = perm_[i];
    for (int i = 0; i < 512; ++i) gradient_[i] = std::uint8_t(perm_[i] % 12);
}

double SimplexNoise::operator()(double x, double y, double z) const {
    constexpr double F3 = 1.0 / 3.0;  // skew to the cubic lattice
    constexpr double G3 = 1.0 / 6.0;  // and back

    const double s = (x + y + z) * F3;
    const int i = fast_floor(x + s), j = fast_floor(y + s), k = fast_floor(z + s);
    const double t = (i + j + k) * G3;
    const double x0 = x - (i - t), y0 = y - (j - t), z0 = z - (k - t);

    // Which of the six tetrahedra of the skewed cube holds the point: walk
    // from the origin corner along the axes in decreasing order of offset.
    // Written with comparisons instead of branches (the order is random).
    const int xy = x0 >= y0, yz = y0 >= z0, xz = x0 >= z0;
    const int i1 = xy & xz, j1 = (!xy) & yz, k1 = (!xz) & (!yz);
    const int i2 = xy | xz, j2 = (!xy) | yz, k2 = !(xz & yz);
    const double x1 = x0 - i1 + G3, y1 = y0 - j1 + G3, z1 = z0 - k1 + G3;
    const double x2 = x0 - i2 + 2 * G3, y2 = y0 - j2 + 2 * G3, z2 = z0 - k2 + 2 * G3;
    const double x3 = x0 - 1 + 3 * G3, y3 = y0 - 1 + 3 * G3, z3 = z0 - 1 + 3 * G3;

    const int ii = i & 255, jj = j & 255, kk = k & 255;
    const int g0 = gradient_[ii + perm_[jj + perm_[kk]]];
    const int g1 = gradient_[ii + i1 + perm_[jj + j1 + perm_[kk + k1]]];
    const int g2 = gradient_[ii + i2 + perm_[jj + j2 + perm_[kk + k2]]];
    const int g3 = gradient_[ii + 1 + perm_[jj + 1 + perm_[kk + 1]]];

    return kNoiseScale * (corner(g0, x0, y0, z0) + corner(g1, x1, y1, z1) + corner(g2, x2, y2, z2) +
                    corner(g3, x3, y3, z3));
}

SimplexNoise::Lanes SimplexNoise::operator()(const Lanes& x, const Lanes& y, const Lanes& z) const {
#if defined(__x86_64__)
    if (__builtin_cpu_supports("avx2")) return lanes_avx2(x, y, z);
#endif
    Lanes out;
    for (int l = 0; l < 4; ++l) out[l] = (*this)(x[l], y[l], z[l]);
    return out;
}

#if defined(__x86_64__)
namespace {

// fast_floor in four lanes: the truncation, less one where it rounded up.
__attribute__((target("avx2"))) inline __m256d floor4(__m256d v) {
    const __m256d t = _mm256_cvtepi32_pd(_mm256_cvttpd_epi32(v));
    return _mm256_sub_pd(t, _mm256_and_pd(_mm256_cmp_pd(v, t, _CMP_LT_OQ), _mm256_set1_pd(1.0)));
}

// corner() in four lanes, gradients (gx, gy, gz) per lane: (R² − r²)⁴ (g · d),
// R² − r² clamped at 0 as std::max(v, 0) does (max(0, v) keeps v's −0, as
// it does).
__attribute__((target("avx2"))) inline __m256d corner4(const double* gx, const double* gy, const double* gz,
                                                       __m256d x, __m256d y, __m256d z) {
    __m256d r = _mm256_sub_pd(_mm256_set1_pd(kRadius2), _mm256_mul_pd(x, x));
    r = _mm256_sub_pd(_mm256_sub_pd(r, _mm256_mul_pd(y, y)), _mm256_mul_pd(z, z));
    r = _mm256_max_pd(_mm256_setzero_pd(), r);
    r = _mm256_mul_pd(r, r);
    const __m256d dot =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_load_pd(gx), x), _mm256_mul_pd(_mm256_load_pd(gy), y)),
                      _mm256_mul_pd(_mm256_load_pd(gz), z));
    return _mm256_mul_pd(_mm256_mul_pd(r, r), dot);
}

}  // namespace

// The operator above in four lanes, operation for operation: its integer
// floors and their sums are exact in doubles, its comparisons become masks
// and its corner indices are looked up lane by lane. Compiled for AVX2
// alone, not FMA, so no product and sum are fused (operator() has none).
__attribute__((target("avx2"))) SimplexNoise::Lanes SimplexNoise::lanes_avx2(const Lanes& px, const Lanes& py,
                                                                             const Lanes& pz) const {
    constexpr double F3 = 1.0 / 3.0, G3 = 1.0 / 6.0;
    const __m256d x = _mm256_loadu_pd(px.data()), y = _mm256_loadu_pd(py.data()), z = _mm256_loadu_pd(pz.data());
    const __m256d one = _mm256_set1_pd(1.0);
    const __m256d s = _mm256_mul_pd(_mm256_add_pd(_mm256_add_pd(x, y), z), _mm256_set1_pd(F3));
    const __m256d i = floor4(_mm256_add_pd(x, s)), j = floor4(_mm256_add_pd(y, s)), k = floor4(_mm256_add_pd(z, s));
    const __m256d t = _mm256_mul_pd(_mm256_add_pd(_mm256_add_pd(i, j), k), _mm256_set1_pd(G3));
    const __m256d x0 = _mm256_sub_pd(x, _mm256_sub_pd(i, t)), y0 = _mm256_sub_pd(y, _mm256_sub_pd(j, t)),
                  z0 = _mm256_sub_pd(z, _mm256_sub_pd(k, t));
    const __m256d xy = _mm256_cmp_pd(x0, y0, _CMP_GE_OQ), yz = _mm256_cmp_pd(y0, z0, _CMP_GE_OQ),
                  xz = _mm256_cmp_pd(x0, z0, _CMP_GE_OQ);
    // The offsets of the second and third corners, 0 or 1 (masks and 1.0).
    const __m256d i1 = _mm256_and_pd(_mm256_and_pd(xy, xz), one), j1 = _mm256_and_pd(_mm256_andnot_pd(xy, yz), one),
                  k1 = _mm256_andnot_pd(_mm256_or_pd(xz, yz), one);
    const __m256d i2 = _mm256_and_pd(_mm256_or_pd(xy, xz), one),
                  j2 = _mm256_or_pd(_mm256_andnot_pd(xy, one), _mm256_and_pd(yz, one)),
                  k2 = _mm256_andnot_pd(_mm256_and_pd(xz, yz), one);
    const __m256d g1c = _mm256_set1_pd(G3), g2c = _mm256_set1_pd(2 * G3), g3c = _mm256_set1_pd(3 * G3);
    const __m256d x1 = _mm256_add_pd(_mm256_sub_pd(x0, i1), g1c), y1 = _mm256_add_pd(_mm256_sub_pd(y0, j1), g1c),
                  z1 = _mm256_add_pd(_mm256_sub_pd(z0, k1), g1c);
    const __m256d x2 = _mm256_add_pd(_mm256_sub_pd(x0, i2), g2c), y2 = _mm256_add_pd(_mm256_sub_pd(y0, j2), g2c),
                  z2 = _mm256_add_pd(_mm256_sub_pd(z0, k2), g2c);
    const __m256d x3 = _mm256_add_pd(_mm256_sub_pd(x0, one), g3c), y3 = _mm256_add_pd(_mm256_sub_pd(y0, one), g3c),
                  z3 = _mm256_add_pd(_mm256_sub_pd(z0, one), g3c);
    // The four corners' gradients, lane by lane.
    alignas(32) double fi[4], fj[4], fk[4], ci1[4], cj1[4], ck1[4], ci2[4], cj2[4], ck2[4];
    _mm256_store_pd(fi, i), _mm256_store_pd(fj, j), _mm256_store_pd(fk, k);
    _mm256_store_pd(ci1, i1), _mm256_store_pd(cj1, j1), _mm256_store_pd(ck1, k1);
    _mm256_store_pd(ci2, i2), _mm256_store_pd(cj2, j2), _mm256_store_pd(ck2, k2);
    alignas(32) double gx[4][4], gy[4][4], gz[4][4];  // [corner][lane]
    for (int l = 0; l < 4; ++l) {
        const int ii = int(fi[l]) & 255, jj = int(fj[l]) & 255, kk = int(fk[l]) & 255;
        const int a1 = int(ci1[l]), b1 = int(cj1[l]), c1 = int(ck1[l]);
        const int a2 = int(ci2[l]), b2 = int(cj2[l]), c2 = int(ck2[l]);
        const int g[4] = {gradient_[ii + perm_[jj + perm_[kk]]],
                          gradient_[ii + a1 + perm_[jj + b1 + perm_[kk + c1]]],
                          gradient_[ii + a2 + perm_[jj + b2 + perm_[kk + c2]]],
                          gradient_[ii + 1 + perm_[jj + 1 + perm_[kk + 1]]]};
        for (int c = 0; c < 4; ++c) gx[c][l] = kGrad[g[c]][0], gy[c][l] = kGrad[g[c]][1], gz[c][l] = kGrad[g[c]][2];
    }
    const __m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(corner4(gx[0], gy[0], gz[0], x0, y0, z0),
                                                                  corner4(gx[1], gy[1], gz[1], x1, y1, z1)),
                                                    corner4(gx[2], gy[2], gz[2], x2, y2, z2)),
                                      corner4(gx[3], gy[3], gz[3], x3, y3, z3));
    Lanes out;
    _mm256_storeu_pd(out.data(), _mm256_mul_pd(_mm256_set1_pd(kNoiseScale), sum));
    return out;
}
#else
SimplexNoise::Lanes SimplexNoise::lanes_avx2(const Lanes&, const Lanes&, const Lanes&) const {
    throw Error("internal: AVX2 lanes on a processor without them");
}
#endif

Fbm::Fbm(const NoiseParams& params)
    : simplex_(params.seed), octaves_(params.octave_count()),
      k_(params.k) {
    params.validate();
    base_frequency_ = params.frequency / params.resolution;
    // At angle 0 and stretch 1 the transform below is exact (cos 0 = 1,
    // sin 0 = 0): the paper's fBm, value for value.
    along_x_ = std::cos(radians(params.angle));
    along_y_ = std::sin(radians(params.angle));
    inv_stretch_ = 1.0 / params.stretch;
    bands_per_voxel_ = params.bands / params.resolution;
    fold_ = params.bands > 0.0 ? params.fold : 1.0;
    veins_ = params.veins;
    layers_ = params.layers;
    if (layers_) {
        // The warp is the paper's fBm, smooth: k shapes the profile instead,
        // and the warp's finer octaves would crinkle every layer at the
        // scale of a few voxels, which banded stone's layers are not.
        k_ = kLayerWarpRatio;
        octaves_ = std::min(octaves_, kLayerWarpOctaves);
        // Profile octaves up to half a cycle per voxel: finer layers alias.
        while (profile_octaves_ < 30 && std::ldexp(bands_per_voxel_, profile_octaves_) <= 0.5) ++profile_octaves_;
        profile_octaves_ = std::max(1, profile_octaves_);
        profile_k_ = params.k;
    }
    if (veins_) {
        vein_frequency_ = params.vein_frequency / params.resolution;
        vein_width_ = params.vein_width;
        while (vein_octaves_ < kVeinOctaves && std::ldexp(vein_frequency_, vein_octaves_) <= 0.25) ++vein_octaves_;
        vein_octaves_ = std::max(1, vein_octaves_);
        vein_offset_.resize(3 * std::size_t(vein_octaves_));
        for (std::size_t i = 0; i < vein_offset_.size(); ++i)
            vein_offset_[i] =
                256.0 * to_unit_double(splitmix64((std::uint64_t(params.seed) << 32) ^ (i + kVeinSalt)));
    }
    warp_ = params.warp * params.resolution / amplitude_sum(k_, octaves_);
    offset_.resize(3 * std::size_t(octaves_));
    for (std::size_t i = 0; i < offset_.size(); ++i)
        offset_[i] = 256.0 * to_unit_double(splitmix64((std::uint64_t(params.seed) << 32) ^ i));
    // Salted apart from the warp's, so that the two fBms are independent.
    profile_offset_.resize(3 * std::size_t(profile_octaves_));
    for (std::size_t i = 0; i < profile_offset_.size(); ++i)
        profile_offset_[i] =
            256.0 * to_unit_double(splitmix64((std::uint64_t(params.seed) << 32) ^ (i + kProfileSalt)));
}

double Fbm::frequency(int i) const { return std::ldexp(base_frequency_, i); }

double Fbm::amplitude(int i) const { return std::pow(k_, i + 1); }

double Fbm::structure_bound() const {
    if (layers_) return amplitude_sum(profile_k_, profile_octaves_);
    return bands_per_voxel_ > 0.0 ? 1.0 : amplitude_sum(k_, octaves_);
}

double Fbm::bound() const { return structure_bound() + (veins_ ? 1.0 : 0.0); }

Fbm::Lanes Fbm::vein_field(const Lanes& x, const Lanes& y, const Lanes& z) const {
    Lanes sum{}, at_x, at_y, at_z;
    double fr = vein_frequency_, amp = kVeinRatio;
    for (int i = 0; i < vein_octaves_; ++i) {
        const double* o = &vein_offset_[3 * std::size_t(i)];
        for (int l = 0; l < 4; ++l) at_x[l] = x[l] * fr + o[0], at_y[l] = y[l] * fr + o[1], at_z[l] = z[l] * fr + o[2];
        const Lanes n = simplex_(at_x, at_y, at_z);
        for (int l = 0; l < 4; ++l) sum[l] += amp * n[l];
        fr *= 2.0;
        amp *= kVeinRatio;
    }
    const double bound = amplitude_sum(kVeinRatio, vein_octaves_);
    for (double& v : sum) v /= bound;
    return sum;
}

double Fbm::amplitude_sum(double ratio, int octaves) const {
    double sum = 0.0, amp = ratio;
    for (int i = 0; i < octaves; ++i, amp *= ratio) sum += amp;
    return sum;
}

Fbm::Lanes Fbm::layer_profile(const Lanes& t) const {
    Lanes sum{}, at_x;
    double fr = 1.0, amp = profile_k_;
    for (int i = 0; i < profile_octaves_; ++i) {
        const double* o = &profile_offset_[3 * std::size_t(i)];
        // Simplex noise along a line through the lattice: a 1-D noise.
        for (int l = 0; l < 4; ++l) at_x[l] = t[l] * fr + o[0];
        const Lanes n = simplex_(at_x, Lanes{o[1], o[1], o[1], o[1]}, Lanes{o[2], o[2], o[2], o[2]});
        for (int l = 0; l < 4; ++l) sum[l] += amp * n[l];
        fr *= 2.0;
        amp *= profile_k_;
    }
    return sum;
}

double Fbm::operator()(double px, double py, double pz) const {
    return (*this)(Lanes{px, px, px, px}, Lanes{py, py, py, py}, Lanes{pz, pz, pz, pz})[0];
}

// Four positions through the same operations, lane by lane, the noise
// four at a time (SimplexNoise's lanes): each lane's value is what one
// position alone would give.
Fbm::Lanes Fbm::operator()(const Lanes& px, const Lanes& py, const Lanes& pz) const {
    // Into the frame of the structure: u along the bands (stretched), w across.
    Lanes x, y, z, y_noise;
    for (int l = 0; l < 4; ++l) {
        x[l] = (along_x_ * px[l] + along_y_ * py[l]) * inv_stretch_;
        y[l] = -along_y_ * px[l] + along_x_ * py[l];
        z[l] = pz[l] * inv_stretch_;
        // The noise's coordinate across the layers; with bands the warp
        // reads it at ε·w (at ε = 1 the product is exact: the isotropic warp
        // as before).
        y_noise[l] = fold_ * y[l];
    }
    Lanes sum{}, at_x, at_y, at_z;
    double fr = base_frequency_, amp = k_;
    for (int i = 0; i < octaves_; ++i) {
        const double* o = &offset_[3 * std::size_t(i)];
        for (int l = 0; l < 4; ++l)
            at_x[l] = x[l] * fr + o[0], at_y[l] = y_noise[l] * fr + o[1], at_z[l] = z[l] * fr + o[2];
        const Lanes n = simplex_(at_x, at_y, at_z);
        for (int l = 0; l < 4; ++l) sum[l] += amp * n[l];
        fr *= 2.0;
        amp *= k_;
    }
    Lanes value = sum;
    if (layers_) {
        Lanes t;
        for (int l = 0; l < 4; ++l) t[l] = bands_per_voxel_ * (y[l] + warp_ * sum[l]);
        value = layer_profile(t);
    } else if (bands_per_voxel_ > 0.0) {
        for (int l = 0; l < 4; ++l) value[l] = std::sin(2.0 * kPiD * bands_per_voxel_ * (y[l] + warp_ * sum[l]));
    }
    if (!veins_) return value;
    // Inside a vein, below every value of the structure and darkest along
    // the veins' zero set; outside, the structure itself.
    const Lanes field = vein_field(px, py, pz);
    for (int l = 0; l < 4; ++l) {
        const double d = std::abs(field[l]);
        if (d < vein_width_) value[l] = d / vein_width_ - 1.0 - structure_bound();
    }
    return value;
}

void fbm_slice(const Fbm& fbm, int resolution, int k, float* out) {
    const double z = k + 0.5;
    const Fbm::Lanes zs{z, z, z, z};
    for (int j = 0; j < resolution; ++j) {
        const double y = j + 0.5;
        // Four voxels of the row at a time; past the row's end a lane
        // repeats its last voxel.
        for (int i = 0; i < resolution; i += 4) {
            Fbm::Lanes xs;
            for (int l = 0; l < 4; ++l) xs[l] = std::min(i + l, resolution - 1) + 0.5;
            const Fbm::Lanes v = fbm(xs, Fbm::Lanes{y, y, y, y}, zs);
            for (int l = 0; l < 4 && i + l < resolution; ++l) out[std::size_t(j) * resolution + i + l] = float(v[l]);
        }
    }
}

std::vector<float> fbm_volume(const NoiseParams& params) {
    const Fbm fbm(params);
    const int s = params.resolution;
    const std::size_t slice = std::size_t(s) * s;
    std::vector<float> out(slice * s);
    tbb::parallel_for(0, s, [&](int k) { fbm_slice(fbm, s, k, &out[k * slice]); });
    return out;
}

}  // namespace jade
