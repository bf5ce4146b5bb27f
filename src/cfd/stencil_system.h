// A symmetric 7-point linear system on a box of unknowns: the shape of every implicit solve of
// the fluid solver (the pressure Poisson equation and the implicit momentum equations on the
// staggered grid). Plain data; the solvers behind `PressureSolver` read it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace quarry::cfd {

// Row of unknown P: diagonal(P) x_P − Σ_N conductance(P,N) x_N = b_P with
// diagonal(P) = mass(P) + Σ_axes boundary(axis, P) + Σ_N conductance(P, N) over every
// neighbour N that exists (periodic axes wrap; an axis of one unknown has no neighbours).
// A neighbour that is not active enters the diagonal only: it is a Dirichlet value 0 at its
// position. An inactive unknown has the row x_P = b_P (its b must be 0 for a homogeneous
// condition). All coefficients ≥ 0; the matrix is symmetric positive semi-definite, singular
// only without mass, without boundary terms (all Neumann or periodic) — then the solution is
// defined up to a constant and the solvers return the one with zero mean over active unknowns.
struct StencilSystem {
  std::array<int, 3> size{1, 1, 1};  // unknowns along x, y, z (≥ 1)
  std::array<bool, 3> periodic{false, false, false};
  // conductance[a][P] couples P with its low neighbour along axis a (P − e_a, or the last
  // unknown of the row when periodic and P is first). Units: those of the row (the fluid
  // solver uses volume-integrated rows). Unused (keep 0) for the first unknown of a
  // non-periodic axis.
  std::array<std::vector<double>, 3> conductance;
  // Dirichlet terms of the faces on the box boundary along each axis (a conductance to a value
  // held at the face); coarsened like conductances along that axis.
  std::array<std::vector<double>, 3> boundary;
  std::vector<double> mass;          // a diagonal term with no spatial coupling (ρε/dt V + βV)
  std::vector<std::uint8_t> active;  // 1: an unknown; 0: held at 0

  std::size_t count() const {
    return static_cast<std::size_t>(size[0]) * static_cast<std::size_t>(size[1]) *
           static_cast<std::size_t>(size[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(size[0]) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(size[1]) * static_cast<std::size_t>(k));
  }
  // Sizes every array for `size` and fills them with zeros (active with 1).
  void reset(std::array<int, 3> new_size, std::array<bool, 3> new_periodic) {
    size = new_size;
    periodic = new_periodic;
    const std::size_t n = count();
    for (int a = 0; a < 3; ++a) {
      conductance[a].assign(n, 0.0);
      boundary[a].assign(n, 0.0);
    }
    mass.assign(n, 0.0);
    active.assign(n, 1);
  }
};

}  // namespace quarry::cfd
