#include "jade/render/media/homogeneous.h"

#include "jade/core/error.h"

namespace jade {

HomogeneousMedium::HomogeneousMedium(const Spectrum& sigma_s, const Spectrum& sigma_a)
    : props_{sigma_s, sigma_a} {
    for (int c = 0; c < 3; ++c)
        if (!(sigma_s[c] >= 0.f && sigma_a[c] >= 0.f) || !is_finite(sigma_s + sigma_a))
            throw Error("medium coefficients must be finite and non-negative");
}

}  // namespace jade
