// SPDX-License-Identifier: GPL-2.0-or-later
// The app of docs/tutorial.md: the gantry crane's generated rhs (models/gantry_crane.mbs,
// generated with --state minimal) integrated by the runtime's RK4. The load starts
// 0.02 rad aside with the cart at rest and no force; the app measures the period of the
// swing from the upward zero crossings of theta and prints it beside the small-angle
// period 2 pi / omega, omega^2 = g (M + m) / (M l) (the cart recoils as the load swings).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "gantry_crane/gantry_crane.hpp"
#include "mbsc/runtime/rk4.hpp"

namespace crane = mbsc_gen::gantry_crane;

namespace {
int index_of(const char* const* names, int n, const char* name) {
  for (int i = 0; i < n; ++i)
    if (std::strcmp(names[i], name) == 0) return i;
  std::fprintf(stderr, "no name %s\n", name);
  return -1;
}
}  // namespace

int main() {
  std::vector<double> p(crane::kParamDefaults, crane::kParamDefaults + crane::kNp);
  auto param = [&](const char* name) { return p[static_cast<std::size_t>(index_of(crane::kParamNames, crane::kNp, name))]; };
  const int theta = index_of(crane::kStateNames, crane::kNx, "theta");
  if (theta < 0) return 1;
  std::vector<double> x(crane::kNx, 0.0);  // minimal state: x, theta, v, w
  x[static_cast<std::size_t>(theta)] = 0.02;
  double u[crane::kNin] = {0.0};  // the force F
  auto rhs = [&](double t, const double* s, double* sdot) { return crane::rhs(t, s, u, p.data(), sdot); };
  // Upward zero crossings of theta, located by linear interpolation within a step.
  std::vector<double> crossings;
  double t_prev = 0.0, th_prev = x[static_cast<std::size_t>(theta)];
  const int status = mbsc::runtime::rk4_integrate(rhs, 0.0, 20.0, 20000, x, [&](double t, const std::vector<double>& s) {
    const double th = s[static_cast<std::size_t>(theta)];
    if (th_prev < 0.0 && th >= 0.0) crossings.push_back(t_prev + (t - t_prev) * (-th_prev) / (th - th_prev));
    t_prev = t;
    th_prev = th;
  });
  if (status != 0 || crossings.size() < 2) {
    std::fprintf(stderr, "the run failed (status %d, %zu crossings)\n", status, crossings.size());
    return 1;
  }
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  const double M = param("M"), m = param("m"), l = param("l"), g = param("g");
  const double omega = std::sqrt(g * (M + m) / (M * l));
  std::printf("swing period %.5f s over %zu periods; small-angle 2 pi / omega = %.5f s\n", period, crossings.size() - 1,
              2 * M_PI / omega);
  return 0;
}
