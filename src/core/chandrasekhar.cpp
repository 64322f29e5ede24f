#include "jade/core/chandrasekhar.h"

#include <cmath>

namespace jade {

namespace {

// Gauss–Legendre nodes and weights on [lo, hi], by Newton's method on P_n.
void legendre_rule(int n, double lo, double hi, std::vector<double>& nodes, std::vector<double>& weights) {
    for (int i = 0; i < n; ++i) {
        double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int k = 0; k < 100; ++k) {
            double p0 = 1, p1 = x;
            for (int m = 2; m <= n; ++m) {
                const double p2 = ((2 * m - 1) * x * p1 - (m - 1) * p0) / m;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (x * p1 - p0) / (x * x - 1);
            const double dx = p1 / dp;
            x -= dx;
            if (std::abs(dx) < 1e-15) break;
        }
        nodes.push_back(lo + 0.5 * (hi - lo) * (x + 1));
        weights.push_back((hi - lo) / ((1 - x * x) * dp * dp));  // 2/((1−x²)P'²) scaled to [lo, hi]
    }
}

// 1 − θ cot θ without the cancellation near θ = 0 (θ²/3 + θ⁴/45 + 2θ⁶/945 there).
double one_minus_theta_cot(double t) {
    if (t < 1e-2) {
        const double t2 = t * t;
        return t2 / 3.0 + t2 * t2 / 45.0 + 2.0 * t2 * t2 * t2 / 945.0;
    }
    return 1.0 - t / std::tan(t);
}

}  // namespace

ChandrasekharH::ChandrasekharH(double albedo) : a_(albedo) {
    // The exact integral, rather than the iteration of the integral equation,
    // which contracts ever more slowly as a → 1 (at a = 1 − 10⁻⁶, 500 sweeps
    // leave α₁ 20 % low): ln H(μ) = −(μ/π) ∫₀^{π/2} ln(1 − a θ cot θ) /
    // (cos²θ + μ² sin²θ) dθ (Chandrasekhar 1960, §39, for isotropic
    // scattering). The logarithm is singular at θ = 0 when a = 1, so the
    // panels crowd there (edges at (π/2)(i/16)²).
    const int panels = 16;
    for (int p = 0; p < panels; ++p) {
        const double lo = M_PI_2 * (double(p) / panels) * (double(p) / panels);
        const double hi = M_PI_2 * (double(p + 1) / panels) * (double(p + 1) / panels);
        legendre_rule(64, lo, hi, theta_, theta_w_);
    }
    for (std::size_t k = 0; k < theta_.size(); ++k) {
        const double t = theta_[k];
        log_term_.push_back(theta_w_[k] * std::log((1.0 - a_) + a_ * one_minus_theta_cot(t)));
        cos2_.push_back(std::cos(t) * std::cos(t));
        sin2_.push_back(std::sin(t) * std::sin(t));
    }
    legendre_rule(48, 0.0, 1.0, mu_, w_);
    for (double mu : mu_) H_.push_back((*this)(mu));
}

double ChandrasekharH::operator()(double mu) const {
    double s = 0;
    for (std::size_t k = 0; k < theta_.size(); ++k) s += log_term_[k] / (cos2_[k] + mu * mu * sin2_[k]);
    return std::exp(-mu / M_PI * s);
}

double ChandrasekharH::moment(int n) const {
    double s = 0;
    for (std::size_t j = 0; j < mu_.size(); ++j) s += w_[j] * (n == 0 ? 1.0 : mu_[j]) * H_[j];
    return s;
}

double ChandrasekharH::diffuse_albedo() const { return 1.0 - 2.0 * std::sqrt(1.0 - a_) * moment(1); }

}  // namespace jade
