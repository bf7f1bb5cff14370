// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Eigenvalues of a state matrix A(p) along a parameter sweep (issue 13, `mbsc eig`):
///  * sweep_eigenvalues: the eigenvalues and eigenvectors at every grid point, each mode
///    followed continuously from point to point (an optimal assignment against a linear
///    prediction from the two previous points, eigenvector overlap breaking ties), so that
///    curves never swap where real parts cross and conjugate pairs stay pairs;
///  * stability_crossings: where a mode's real part changes sign, refined by root finding
///    on the matrix itself (not the grid) to a relative tolerance of the sweep's range;
///  * ratio: a component ratio of an eigenvector (steer to lean of a bicycle's weave);
///  * write_sweep_csv: the tracked curves as CSV.
/// Errors follow the convention of src/run: a false return and a message in `error`.
#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace mbsc::run {

/// The state matrix at a parameter value: false, with a reason in `why`, where it cannot
/// be formed (no reference state there, a singular mass matrix, ...).
using MatrixAt = std::function<bool(double param, Eigen::MatrixXd& A, std::string& why)>;

/// A sweep's eigenvalues, mode by mode. Modes are numbered at the first grid point by real
/// part, then imaginary part (ascending), and keep their number along the sweep.
struct TrackedSweep {
  std::vector<double> param;                               ///< the grid
  std::vector<std::vector<std::complex<double>>> values;  ///< [point][mode]
  /// [point][mode]: unit eigenvectors. At the first point the largest component (the first
  /// of equal ones) is real and positive. From there on a real mode's vector is real, its
  /// sign chosen so that its product with the previous point's vector of the same mode is
  /// positive; the upper member (Im > 0) of a conjugate pair is turned so that this product
  /// is real and positive, and the lower member's vector is its conjugate. (Where two real
  /// modes meet and become a pair, the lower member's vector may thus change sign.)
  std::vector<std::vector<Eigen::VectorXcd>> vectors;
  int modes() const { return values.empty() ? 0 : static_cast<int>(values.front().size()); }
};

/// Eigenvalues of A(grid[k]) for every k, tracked. The grid must be non-empty, finite and
/// strictly monotonic (increasing or decreasing). `param_name` names the parameter in
/// messages ("cannot form the state matrix at v = 1.5: ..."). False with `error` for a bad
/// grid, a point where `A` fails, a matrix that is empty, not square, changes size or has
/// a non-finite entry, or an eigensolver that does not converge.
bool sweep_eigenvalues(const MatrixAt& A, const std::vector<double>& grid, TrackedSweep& out, std::string& error,
                       const std::string& param_name = "p");

/// A mode's real part crossing zero between two grid points.
struct StabilityCrossing {
  int mode = 0;                    ///< the mode's number in the sweep (0-based)
  double param = 0.0;              ///< where Re(lambda) = 0, refined
  std::complex<double> value;      ///< the eigenvalue there (Im >= 0 for a complex pair)
  bool becomes_stable = false;     ///< Re goes from >= 0 to < 0 in the grid's direction
  /// The stable side is marginal: |Re| within kMarginalTolerance of zero there (a
  /// conservative system's oscillation, neither growing nor decaying to first order), as
  /// where a rolling disc's unstable real pair meets at zero and leaves as an imaginary pair.
  bool marginal = false;
};

/// Relative size (of the largest |lambda| at the point) under which a real part counts as
/// zero: a conservative system's imaginary pairs come out of the eigensolver with real
/// parts of rounding size and random sign, which are not crossings. A mode crosses where it
/// goes from unstable (Re above this) to stable (below minus this) or marginal, or back.
constexpr double kMarginalTolerance = 1e-9;

/// Relative size under which an eigenvalue counts as zero: a mode with
/// |lambda| <= kZeroModeTolerance * (the largest |lambda| at the bracket's two points) at
/// both ends of a bracket is not a crossing (the zero eigenvalues of cyclic coordinates).
/// Simple zeros come out of the eigensolver near 1e-16 * scale, but a defective zero (a
/// coordinate drifting at a constant rate: a Jordan block of two) near the square root of
/// the rounding, 1e-8 * scale, with a sign that changes from point to point; hence 1e-6.
/// A genuine crossing is missed only where the mode stays this small at both grid points
/// around it (a grid step below 1e-6 of the scale over the mode's rate of change).
constexpr double kZeroModeTolerance = 1e-6;

/// A mode whose |lambda| stays below this fraction of the largest |lambda| of the whole
/// sweep at every point is a zero mode too (a symmetry's double zero that is not cyclic in
/// the columns, split by rounding into 1e-6-size values of changing sign, most where other
/// eigenvalues pass through zero and make the block larger).
constexpr double kZeroModeSweepTolerance = 1e-5;

/// Every sign change of a tracked mode's real part between consecutive grid points, refined
/// by a bracketing root finder (Illinois' regula falsi, with bisection where it stalls) on
/// Re(lambda(p)), lambda followed inside the bracket as the eigenvalue of A(p) nearest the
/// interpolation between the bracket's ends. Ends when the bracket is at most
/// tol * |range of the grid| wide. A complex pair gives one crossing (the member with
/// Im > 0). Sorted by parameter in the grid's direction, then by mode. False with `error`
/// where A cannot be formed at a trial point (the message names it).
bool stability_crossings(const MatrixAt& A, const TrackedSweep& sweep, std::vector<StabilityCrossing>& out,
                         std::string& error, double tol = 1e-12, const std::string& param_name = "p");

/// v[num] / v[den] (0-based components): for a bicycle's state (lean, steer, rates),
/// ratio(v, 1, 0) is the steer-to-lean ratio whose magnitude and phase (std::abs, std::arg)
/// describe the mode's shape. Independent of the vector's scaling and phase. Infinite or
/// NaN where v[den] is 0; throws std::out_of_range for an index outside v.
std::complex<double> ratio(const Eigen::VectorXcd& v, int num, int den);

/// The sweep as CSV: a header `<param_name>,re_1,im_1,re_2,im_2,...` (modes numbered from 1
/// as in the sweep, real and imaginary parts of each), then one row per grid point. Every
/// number is written in the shortest form that reads back to the same double (full
/// precision, byte-identical run to run).
void write_sweep_csv(std::ostream& os, const TrackedSweep& sweep, const std::string& param_name);

}  // namespace mbsc::run
