// Deck writer: SimulationSpec → YAML deck text (docs/deck.md) that the deck parser reads back
// into the same values, so that a checkpoint can carry the effective spec of a world built
// without a deck file, and users can see the deck a run actually used.
#pragma once

#include <string>

#include "core/simulation_spec.h"

namespace quarry {

// Writes every section and every key the parser reads, defaults included, from `spec`.
// Doubles are written in their shortest round-trip form, so that
// parse_deck_string(write_deck(spec)) gives the same bits and writing that again gives the same
// text. Left out: optional values that are absent (impact_speed, count/mass, mass_rate, a
// monitor's region, export: when not enabled, calculix time and density, the domain's periodic
// when no axis is), keys of other variants (a plane's scale, a Hertz-Mindlin interaction's
// stiffness, the Rayleigh fraction beside a fixed time step), a negative skin (automatic) and
// stop times of 1e300 (never).
// STL paths are written as stored (the parser stores them absolute). A log-normal size is
// written as its median radius exp(log_mean), chosen so that its logarithm is log_mean exactly.
// Locations and deck_path are not written. Cost: linear in the size of the spec.
std::string write_deck(const SimulationSpec& spec);

}  // namespace quarry
