#pragma once
// Chandrasekhar's H-function of isotropic scattering (Chandrasekhar 1960,
// "Radiative Transfer", §39): the exact reflection of a half-space of medium
// with single-scattering albedo a, index-matched. Used as truth by the stiff
// media's tests and by the preview's diffuse albedo (volume/slab_reflectance.h).

#include <vector>

namespace jade {

class ChandrasekharH {
public:
    // H for albedo a in [0, 1], from its exact integral form (§39), by
    // Gauss–Legendre quadrature; the moments on a 48-point rule over [0, 1].
    explicit ChandrasekharH(double albedo);

    double operator()(double mu) const;
    // ∫₀¹ μ^n H(μ) dμ for n = 0, 1 (α₀ is (2/a)(1 − √(1 − a)) exactly, §39).
    double moment(int n) const;
    // The albedo of the half-space under light of radiance 1 from every
    // direction (reflected over incident flux): 1 − 2√(1 − a) α₁, from the
    // albedo 1 − √(1 − a) H(μ₀) of light from cosine μ₀ (§45) weighted by 2μ₀.
    double diffuse_albedo() const;

private:
    double a_;
    std::vector<double> theta_, theta_w_, log_term_, cos2_, sin2_;  // the quadrature over θ
    std::vector<double> mu_, w_, H_;                                // H at the rule's nodes in μ
};

}  // namespace jade
