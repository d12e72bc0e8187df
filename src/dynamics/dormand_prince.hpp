// The Dormand-Prince 5(4) Runge-Kutta pair (J. R. Dormand, P. J. Prince, "A family of embedded
// Runge-Kutta formulae", J. Comp. Appl. Math. 6:19-26, 1980; Hairer, Norsett, Wanner, "Solving
// Ordinary Differential Equations I", table II.5.2): seven stages, the fifth-order solution from
// weights b, and the difference to the embedded fourth-order one from weights e = b - b*, the
// local error estimate that sizes the next step.
#pragma once

#include <array>

namespace linx::dynamics::dormand_prince {

constexpr int kStages = 7;

/// Stage times as fractions of the step.
constexpr std::array<double, kStages> c{0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0};

/// a[i][j], j < i: stage i's state is y + h sum_j a[i][j] k_j.
constexpr std::array<std::array<double, kStages>, kStages> a{{
    {},
    {1.0 / 5.0},
    {3.0 / 40.0, 9.0 / 40.0},
    {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0},
    {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0},
    {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0},
    {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0},
}};

/// The fifth-order weights (the last stage's row of a: the pair is "first same as last").
constexpr std::array<double, kStages> b{
    35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0};

/// b - b*: the fifth-order solution minus the fourth-order one, per stage.
constexpr std::array<double, kStages> e{
    71.0 / 57600.0,      0.0,          -71.0 / 16695.0, 71.0 / 1920.0,
    -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0};

/// The order of the error estimate plus one: a step's error scales as h^5.
constexpr double kErrorExponent = 5.0;

}  // namespace linx::dynamics::dormand_prince
