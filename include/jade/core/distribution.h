#pragma once
// Piecewise-constant densities over [0, 1) and [0, 1)², sampled by inverting
// their cumulative distributions (pbrt-v4's PiecewiseConstant1D/2D): the
// environment image's importance sampling (render/light.h) draws texels in
// proportion to their brightness with them.

#include <glm/vec2.hpp>

#include <vector>

namespace jade {

// A density on [0, 1) proportional to n non-negative values, each constant
// over its 1/n of the interval. All zero (or n = 0 treated as one zero) is
// uniform, so every query stays defined.
class PiecewiseConstant1D {
public:
    explicit PiecewiseConstant1D(std::vector<float> values);
    int size() const { return int(values_.size()); }
    // The integral of the values over [0, 1): their mean.
    double integral() const { return integral_; }
    // x in [0, 1) with density pdf (> 0), and the piece it lies in.
    float sample(float u, float& pdf, int& piece) const;
    float pdf(float x) const;

private:
    std::vector<float> values_;
    std::vector<double> cdf_;  // size() + 1 entries, 0 … 1
    double integral_ = 0.0;
};

// A density on [0, 1)² proportional to an nx × ny grid of values (row y,
// column x at values[y * nx + x]): a row by its marginal, then a column of
// that row by its conditional density.
class PiecewiseConstant2D {
public:
    PiecewiseConstant2D(const std::vector<float>& values, int nx, int ny);
    // A point with its density (> 0).
    glm::vec2 sample(float u1, float u2, float& pdf) const;
    float pdf(const glm::vec2& p) const;

private:
    std::vector<PiecewiseConstant1D> rows_;
    PiecewiseConstant1D marginal_;
};

}  // namespace jade
