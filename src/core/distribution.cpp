#include "jade/core/distribution.h"

#include <algorithm>
#include <cmath>

namespace jade {

PiecewiseConstant1D::PiecewiseConstant1D(std::vector<float> values) : values_(std::move(values)) {
    if (values_.empty()) values_.push_back(0.f);
    const int n = size();
    cdf_.assign(std::size_t(n) + 1, 0.0);
    for (int i = 0; i < n; ++i) {
        const float v = values_[std::size_t(i)];
        if (!(v > 0.f) || !std::isfinite(v)) values_[std::size_t(i)] = 0.f;  // NaN, negative: nothing
        cdf_[std::size_t(i) + 1] = cdf_[std::size_t(i)] + double(values_[std::size_t(i)]) / n;
    }
    integral_ = cdf_.back();
    if (integral_ > 0.0) {
        for (double& c : cdf_) c /= integral_;
    } else {  // nothing to prefer: uniform
        std::fill(values_.begin(), values_.end(), 1.f);
        for (int i = 0; i <= n; ++i) cdf_[std::size_t(i)] = double(i) / n;
    }
    cdf_.back() = 1.0;
}

float PiecewiseConstant1D::sample(float u, float& pdf, int& piece) const {
    const int n = size();
    // The last piece whose cdf lies at or below u; zero-width pieces are
    // skipped because upper_bound finds the first cdf above u.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u));
    piece = std::clamp(int(it - cdf_.begin()) - 1, 0, n - 1);
    while (piece > 0 && !(cdf_[std::size_t(piece) + 1] > cdf_[std::size_t(piece)])) --piece;
    const double lo = cdf_[std::size_t(piece)], hi = cdf_[std::size_t(piece) + 1];
    const double frac = hi > lo ? (double(u) - lo) / (hi - lo) : 0.5;
    pdf = float(double(values_[std::size_t(piece)]) / (integral_ > 0.0 ? integral_ : 1.0));
    const double x = (piece + std::clamp(frac, 0.0, 1.0)) / n;
    return float(std::min(x, std::nextafter(1.0, 0.0)));
}

float PiecewiseConstant1D::pdf(float x) const {
    const int piece = std::clamp(int(x * float(size())), 0, size() - 1);
    return float(double(values_[std::size_t(piece)]) / (integral_ > 0.0 ? integral_ : 1.0));
}

namespace {
std::vector<PiecewiseConstant1D> make_rows(const std::vector<float>& values, int nx, int ny) {
    std::vector<PiecewiseConstant1D> rows;
    rows.reserve(std::size_t(ny));
    for (int y = 0; y < ny; ++y) {
        const auto first = values.begin() + std::ptrdiff_t(y) * nx;
        rows.emplace_back(std::vector<float>(first, first + nx));
    }
    return rows;
}

std::vector<float> integrals(const std::vector<PiecewiseConstant1D>& rows) {
    std::vector<float> out;
    for (const PiecewiseConstant1D& r : rows) out.push_back(float(r.integral()));
    return out;
}
}  // namespace

PiecewiseConstant2D::PiecewiseConstant2D(const std::vector<float>& values, int nx, int ny)
    : rows_(make_rows(values, nx, ny)), marginal_(integrals(rows_)) {}

glm::vec2 PiecewiseConstant2D::sample(float u1, float u2, float& pdf) const {
    float pdf_y, pdf_x;
    int row;
    const float y = marginal_.sample(u2, pdf_y, row);
    int column;
    const float x = rows_[std::size_t(row)].sample(u1, pdf_x, column);
    pdf = pdf_x * pdf_y;
    return {x, y};
}

float PiecewiseConstant2D::pdf(const glm::vec2& p) const {
    const int row = std::clamp(int(p.y * float(rows_.size())), 0, int(rows_.size()) - 1);
    return marginal_.pdf(p.y) * rows_[std::size_t(row)].pdf(p.x);
}

}  // namespace jade
