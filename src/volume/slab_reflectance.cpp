#include "jade/volume/slab_reflectance.h"

#include "jade/core/chandrasekhar.h"

#include <cmath>

namespace jade {

KubelkaMunk kubelka_munk_coefficients(double sigma_s, double sigma_a, double g) {
    const double reduced = sigma_s * (1.0 - g);
    KubelkaMunk km;
    km.K = 2.0 * sigma_a;
    if (reduced <= 0.0) return km;  // nothing scatters back: S = 0
    if (sigma_a <= 0.0) {
        km.S = 0.75 * reduced;
        return km;
    }
    const double albedo = reduced / (reduced + sigma_a);
    const double r_inf = ChandrasekharH(albedo).diffuse_albedo();
    // K/S = (1 − R∞)² / (2 R∞), K–M's R∞ solved for K/S.
    km.S = r_inf > 0.0 ? km.K * 2.0 * r_inf / ((1.0 - r_inf) * (1.0 - r_inf)) : 0.0;
    return km;
}

SlabReflectance kubelka_munk_slab(const KubelkaMunk& km, double d) {
    SlabReflectance out;
    if (km.S <= 0.0) {
        out.T = std::exp(-km.K * d);
        return out;
    }
    const double sd = km.S * d;
    if (km.K <= 0.0) {
        out.R = sd / (1.0 + sd);
        out.T = 1.0 / (1.0 + sd);
        return out;
    }
    const double a = 1.0 + km.K / km.S, b = std::sqrt(a * a - 1.0);
    // Divided through by cosh(x), so that thick slabs do not overflow:
    // R = tanh / (a tanh + b), T = b sech / (a tanh + b).
    const double x = b * sd, e = std::exp(-2.0 * x);
    const double tanh_x = (1.0 - e) / (1.0 + e), sech_x = 2.0 * std::exp(-x) / (1.0 + e);
    const double den = a * tanh_x + b;
    out.R = tanh_x / den;
    out.T = b * sech_x / den;
    return out;
}

}  // namespace jade
