#include "jade/core/direction_fit.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

namespace {
// Where each sum lives in DirectionSums::v.
constexpr int kQ = 0, kQx = 1, kQxx = 4, kQw = 10, kQwx = 13, kQww = 22;
// The narrowest radius a lobe is given (about 0.6°): all the directions
// of a cell alike would otherwise make a cone of no width.
constexpr double kNarrowest = 0.01;
// A lobe whose model direction is shorter than this at the cell's centre
// averages directions too far apart to aim at any of them.
constexpr double kShortestMean = 0.5;

// The upper triangle of a symmetric 3×3 matrix, row by row, as a matrix.
glm::dmat3 symmetric(const double* upper) {
    glm::dmat3 m;
    int k = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) m[i][j] = m[j][i] = upper[k++];
    return m;
}
}  // namespace

void StretchSums::add(double weight, const glm::dvec3& x) {
    q += weight;
    qx += weight * x;
    int k = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) qxx[std::size_t(k++)] += weight * x[i] * x[j];
}

void DirectionSums::add(const StretchSums& s, const glm::vec3& w_in) {
    const glm::dvec3 w(w_in);
    v[kQ] += s.q;
    for (int i = 0; i < 3; ++i) v[std::size_t(kQx + i)] += s.qx[i];
    for (int i = 0; i < 6; ++i) v[std::size_t(kQxx + i)] += s.qxx[std::size_t(i)];
    for (int i = 0; i < 3; ++i) v[std::size_t(kQw + i)] += w[i] * s.q;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[std::size_t(kQwx + 3 * i + j)] += w[i] * s.qx[j];
    int k = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) v[std::size_t(kQww + k++)] += w[i] * w[j] * s.q;
}

std::optional<EllipticCone> DirectionLobe::cone(const glm::vec3& x) const {
    glm::vec3 a;
    for (int i = 0; i < 3; ++i) {
        const auto& row = model[std::size_t(i)];
        a[i] = row[0] + row[1] * x.x + row[2] * x.y + row[3] * x.z;
    }
    const float length = glm::length(a);
    if (!(length > 0.f)) return std::nullopt;
    a /= length;
    glm::vec3 t = major - glm::dot(major, a) * a;
    const float t_length = glm::length(t);
    if (!(t_length > 1e-3f)) return std::nullopt;  // the model turned a right angle within the cell
    t /= t_length;
    return EllipticCone{a, t, glm::cross(a, t), r_major, r_minor};
}

// Least squares: the model A (3×4) minimises Σq |w − A (1, x)|², so
// A = B M⁻¹ with M = Σq (1, x)(1, x)ᵀ and B = Σq w (1, x)ᵀ; the residuals'
// second moment is then (Σq w wᵀ − A Bᵀ) / Σq. With the ridge in M that
// spread exceeds the residuals' by ridge · J Jᵀ (J the model's change
// across the cell): a little more room where the direction turns fast,
// as measured (docs/design.md, "The cells' lobes").
std::optional<DirectionLobe> fit_direction_lobe(const DirectionSums& sums, const DirectionFitSettings& settings) {
    const double* v = sums.v.data();
    const double total = v[kQ];
    if (!(total > 0.0)) return std::nullopt;
    glm::dmat4 M(0.0);  // symmetric: rows and columns alike
    const glm::dmat3 xx = symmetric(v + kQxx);
    M[0][0] = total;
    for (int i = 0; i < 3; ++i) {
        M[0][i + 1] = M[i + 1][0] = v[kQx + i];
        for (int j = 0; j < 3; ++j) M[i + 1][j + 1] = xx[i][j];
        M[i + 1][i + 1] += settings.ridge * total;
    }
    const glm::dmat4 inverse = glm::inverse(M);
    double B[3][4], A[3][4];
    for (int i = 0; i < 3; ++i) {
        B[i][0] = v[kQw + i];
        for (int j = 0; j < 3; ++j) B[i][j + 1] = v[kQwx + 3 * i + j];
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0.0;
            for (int l = 0; l < 4; ++l) s += B[i][l] * inverse[l][j];
            A[i][j] = s;
        }
    glm::dvec3 mean(A[0][0], A[1][0], A[2][0]);
    if (!(glm::length(mean) > kShortestMean)) return std::nullopt;
    mean = glm::normalize(mean);
    const glm::dmat3 ww = symmetric(v + kQww);
    glm::dmat3 C;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = ww[i][j];
            for (int l = 0; l < 4; ++l) s -= A[i][l] * B[j][l];
            C[i][j] = s / total;
        }
    // The spread on the plane tangent to the mean: its 2×2 second moment's
    // principal axes.
    glm::vec3 t1f, t2f;
    orthonormal_basis(glm::vec3(mean), t1f, t2f);
    const glm::dvec3 t1(t1f), t2(t2f);
    const double cxx = glm::dot(t1, C * t1), cyy = glm::dot(t2, C * t2), cxy = glm::dot(t1, C * t2);
    const double half_trace = 0.5 * (cxx + cyy), det = cxx * cyy - cxy * cxy;
    const double root = std::sqrt(std::max(0.0, half_trace * half_trace - det));
    const double var_major = std::max(0.0, half_trace + root), var_minor = std::max(0.0, half_trace - root);
    const double angle = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
    DirectionLobe lobe;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) lobe.model[std::size_t(i)][std::size_t(j)] = float(A[i][j]);
    lobe.major = glm::vec3(std::cos(angle) * t1 + std::sin(angle) * t2);
    // A uniform ellipse of semi-axis R has the variance R²/4 along it.
    lobe.r_major = float(std::max(kNarrowest, settings.margin * 2.0 * std::sqrt(var_major)));
    lobe.r_minor = float(std::max(kNarrowest, settings.margin * 2.0 * std::sqrt(var_minor)));
    if (!(lobe.r_major <= settings.widest)) return std::nullopt;
    return lobe;
}

}  // namespace jade
