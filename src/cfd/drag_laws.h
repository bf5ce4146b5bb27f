// Drag laws of unresolved CFD-DEM: the fluid's drag on one particle from the local slip, void
// fraction and fluid properties, as pure functions (Stokes, Schiller-Naumann, Di Felice,
// Gidaspow, Koch-Hill, Beetstra); sources and validity in each comment and in docs/cfd.md.
#pragma once

#include <array>
#include <optional>
#include <string_view>

#include "core/vec3.h"

namespace quarry::cfd {

// What every law reads, in SI units, at the particle's centre. u and v enter only as the slip
// u − v, so a law does not change when both get the same velocity added (Galilean invariance).
struct DragInput {
  double diameter = 0.0;         // d (m), > 0
  Vec3 particle_velocity;        // v (m/s), finite
  Vec3 fluid_velocity;           // u (m/s), the interstitial fluid velocity, finite
  double porosity = 1.0;         // ε, the fluid (void) volume fraction (1), in (0, 1]
  double fluid_density = 0.0;    // ρ_f (kg/m³), > 0
  double fluid_viscosity = 0.0;  // μ, dynamic viscosity (Pa·s), > 0
};

// Drag on the particle, F = coefficient · (u − v): it points along the slip u − v.
// coefficient (kg/s) is the per-particle momentum-exchange coefficient β_p ≥ 0, which a
// semi-implicit scheme freezes over a step. At zero slip it is the law's limit for |u − v| → 0
// (finite for every law here) and the force is exactly zero.
// Every law returns the drag as it enters model A (set II) of Zhou, Kuang, Chu & Yu 2010
// (J. Fluid Mech. 661:482-510): the pressure-gradient force −V_p ∇p is applied to the particle
// separately. A model-B solver divides the force and the coefficient by ε (Zhou et al. 2010;
// the convention of MFIX's drag_gs "Model B coeff = Model A coeff/EP_g").
struct DragResult {
  Vec3 force;                // N, on the particle
  double coefficient = 0.0;  // β_p (kg/s)
};

// Throws std::invalid_argument naming the quantity and its value unless d > 0, ε in (0, 1],
// ρ_f > 0, μ > 0, all finite, and both velocities finite. Every law below calls it first.
void check_drag_input(const DragInput& input);

// u − v (m/s).
Vec3 slip_velocity(const DragInput& input);
// Re = ρ_f |u − v| d / μ (1): on the interstitial slip. Schiller-Naumann's Reynolds number.
double slip_reynolds_number(const DragInput& input);
// Re_p = ρ_f ε |u − v| d / μ (1): on the superficial slip ε |u − v|, diameter-based. Used by
// Di Felice, Gidaspow's Wen-Yu branch, Koch-Hill (whose papers use half of it, on the radius)
// and Beetstra. Evaluated as ((((ρ_f ε) |u − v|) d) / μ).
double superficial_reynolds_number(const DragInput& input);
// V_p = π d³ / 6 (m³).
double particle_volume(const DragInput& input);
// The Eulerian momentum-exchange coefficient of a cell full of such particles,
// β = n β_p = (1 − ε) β_p / V_p (kg/(m³·s)), n = (1 − ε)/V_p particles per unit volume (1/m³):
// the β of two-fluid models such as Gidaspow's, for which F = β V_p / (1 − ε) (u − v).
double volumetric_exchange_coefficient(double particle_coefficient, const DragInput& input);

// Drag coefficient of a single sphere, Schiller & Naumann (1933):
// C_d = 24/Re (1 + 0.15 Re^0.687) for Re < 1000, 0.44 for Re ≥ 1000 (Newton regime). Re > 0.
double schiller_naumann_drag_coefficient(double reynolds);
// Dallavalle's (1948) single-sphere drag coefficient, C_d = (0.63 + 4.8/√Re)². Re > 0.
double dallavalle_drag_coefficient(double reynolds);
// Di Felice's (1994) voidage exponent χ = 3.7 − 0.65 exp(−(1.5 − log10 Re)²/2), Re ≥ 0
// (χ(0) = 3.7, the limit).
double di_felice_exponent(double reynolds);
// Koch & Hill's (2001) dimensionless drag F = F0(φ) + ½ F3(φ) Re, φ = 1 − ε in [0, 1), Re ≥ 0
// the diameter-based superficial Reynolds number (see koch_hill_drag).
double koch_hill_dimensionless_drag(double solid_fraction, double reynolds);
// Beetstra, van der Hoef & Kuipers' (2007) dimensionless drag F(φ, Re), φ in [0, 1), Re ≥ 0
// superficial (see beetstra_drag).
double beetstra_dimensionless_drag(double solid_fraction, double reynolds);

// Stokes' law with the porosity factor of the AcuSolve-EDEM tutorial's user drag (seed 001,
// usrStokesDrag): F = 3π ε d μ (u − v). For ε = 1 it is Stokes (1851, Trans. Camb. Phil. Soc.
// 9:8-106), the creeping-flow drag of an isolated sphere. Valid for Re ≪ 1 (Oseen's first
// correction, 3/16 Re, is 2 % at Re = 0.1). The factor ε is the seed's choice, not a hindered-
// settling law: it lowers the drag in a crowd, where the laws below raise it.
DragResult stokes_drag(const DragInput& input);

// Schiller & Naumann (1933, Z. Ver. Dtsch. Ing. 77:318-320; often cited as 1935):
// F = ½ ρ_f C_d (π d²/4) |u − v| (u − v), C_d from schiller_naumann_drag_coefficient with
// Re = ρ_f |u − v| d / μ (interstitial slip). A single-particle law: ε enters neither F nor Re,
// as in CFDEMcoupling's SchillerNaumannDrag (model A). Fitted up to Re ≈ 800 (Clift, Grace &
// Weber 1978, Bubbles, Drops and Particles, table 5.2); 0.44 above Re = 1000 is the Newton
// regime's constant. Tends to Stokes as Re → 0, relative excess 0.15 Re^0.687. C_d jumps by
// +0.39 % at Re = 1000 (0.438288… → 0.44).
DragResult schiller_naumann_drag(const DragInput& input);

// Di Felice (1994, Int. J. Multiphase Flow 20(1):153-159, "The voidage function for fluid-
// particle interaction systems"): F = ½ C_d ρ_f (π d²/4) ε² |u − v| (u − v) ε^(−χ), with
// C_d = dallavalle_drag_coefficient(Re_p), χ = di_felice_exponent(Re_p) and Re_p the
// superficial Reynolds number: the single-sphere drag at the superficial velocity ε(u − v)
// times the voidage function ε^(−χ) (as CFDEMcoupling's DiFeliceDrag, model A). Fitted to
// fixed-bed and suspension data over about 1e-2 < Re_p < 1e4, all ε. As Re_p → 0 at ε = 1 it
// tends to 0.96 times Stokes (4.8² = 23.04 instead of 24), relative excess 0.2625 √Re_p.
DragResult di_felice_drag(const DragInput& input);

// Gidaspow (1994, Multiphase Flow and Fluidization, Academic Press), the Eulerian β
// (kg/(m³·s)) of Ding & Gidaspow (1990, AIChE J. 36:523-538):
//   ε < 0.8, Ergun (1952, Chem. Eng. Prog. 48:89-94):
//     β = 150 (1 − ε)² μ / (ε d²) + 1.75 (1 − ε) ρ_f |u − v| / d;
//   ε ≥ 0.8, Wen & Yu (1966, Chem. Eng. Prog. Symp. Ser. 62:100-111):
//     β = ¾ C_d ε (1 − ε) ρ_f |u − v| / d · ε^(−2.65), C_d = Schiller-Naumann's
//     24/Re_p (1 + 0.15 Re_p^0.687) (0.44 from Re_p = 1000) on the superficial Re_p.
// Per particle, F = β V_p / (1 − ε) (u − v) (β over the number density (1 − ε)/V_p); in the
// Wen-Yu branch the (1 − ε) cancels, leaving F = ½ C_d ρ_f (π d²/4) ε^(−1.65) |u − v| (u − v),
// finite at ε = 1, where it is Schiller-Naumann's law (so → Stokes, excess 0.15 Re^0.687).
// Ergun holds for packed beds, Wen-Yu for dilute suspensions; the switch is not continuous:
// at ε = 0.8 and Re → 0, Wen-Yu's β is 0.8^(−2.65)·18/37.5 = 0.867 times Ergun's.
DragResult gidaspow_drag(const DragInput& input);

// Koch & Hill (2001, Annu. Rev. Fluid Mech. 33:619-647) from the lattice-Boltzmann results of
// Hill, Koch & Ladd (2001, J. Fluid Mech. 448:213-241 and 243-278), as used in CFD-DEM by
// CFDEMcoupling's KochHillDrag and Lethe, and in MFIX as reviewed by Benyahia, Syamlal &
// O'Brien (2006, Powder Technol. 162:166-174), whose per-particle form this is:
//   F = 3π μ d ε² (F0 + ½ F3 Re_p) (u − v), φ = 1 − ε, Re_p superficial (the papers' Re is
//   on the radius: Re_p/2),
//   F0 = (1 + 3√(φ/2) + (135/64) φ ln φ + 16.14 φ) / (1 + 0.681 φ − 8.48 φ² + 8.16 φ³), φ < 0.4,
//   F0 = 10 φ / ε³ (Carman-Kozeny), φ ≥ 0.4,   F3 = 0.0673 + 0.212 φ + 0.0232 / ε⁵.
// The papers' F normalises the total fluid force (drag and mean pressure gradient) by Stokes'
// drag at the superficial velocity; the drag alone is ε times it, hence ε². Fitted to random
// arrays, φ up to about 0.6 and moderate Re. Benyahia et al. extend it to all Re and φ (a low-Re
// branch, blending, F3 = 0.9351 φ + 0.03667 below φ = 0.0953); not done here: the one F3 holds
// throughout, as in CFDEMcoupling and Lethe. F0 jumps by +1.04 % at φ = 0.4. At ε = 1, F0 = 1:
// → Stokes, relative excess ½ F3(0) Re_p = 0.04525 Re_p.
DragResult koch_hill_drag(const DragInput& input);

// Beetstra, van der Hoef & Kuipers (2007, AIChE J. 53(2):489-501), monodisperse form:
//   F = 3π μ d ε (u − v) · F(φ, Re_p), Re_p superficial, φ = 1 − ε,
//   F = 10φ/ε² + ε² (1 + 1.5 √φ)
//       + 0.413 Re_p / (24 ε²) · (1/ε + 3 ε φ + 8.4 Re_p^(−0.343))
//                                / (1 + 10^(3φ) Re_p^(−(1 + 4φ)/2)).
// Here F normalises the drag alone (without the mean pressure gradient) by Stokes' drag at the
// superficial velocity, so one factor ε: its dense Stokes limit 10φ/ε² is Carman-Kozeny in that
// normalisation. Fitted to lattice-Boltzmann data, 0.1 ≤ φ ≤ 0.6 and Re_p up to 1000. At ε = 1
// it tends to Stokes with relative excess ≈ 0.1446 Re_p^1.157 as Re_p → 0.
DragResult beetstra_drag(const DragInput& input);

// The laws, for the deck key `drag_law:` (spellings in kDragLawNames).
enum class DragLaw { stokes, schiller_naumann, di_felice, gidaspow, koch_hill, beetstra };

struct DragLawName {
  std::string_view name;
  DragLaw law;
};
// One spelling per law, in the enum's order.
inline constexpr std::array<DragLawName, 6> kDragLawNames{{
    {"stokes", DragLaw::stokes},
    {"schiller_naumann", DragLaw::schiller_naumann},
    {"di_felice", DragLaw::di_felice},
    {"gidaspow", DragLaw::gidaspow},
    {"koch_hill", DragLaw::koch_hill},
    {"beetstra", DragLaw::beetstra},
}};

// The law's spelling. Throws std::invalid_argument for a value outside the enum.
std::string_view drag_law_name(DragLaw law);
// The law spelled `name` (exact, case-sensitive), or nullopt.
std::optional<DragLaw> drag_law_from_name(std::string_view name);

// Evaluates `law` (one of the functions above). Throws std::invalid_argument for bad input or
// a value outside the enum. Cost: one law, a few pow/exp calls.
DragResult drag_force(DragLaw law, const DragInput& input);

}  // namespace quarry::cfd
