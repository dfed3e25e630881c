// Keeping a native RVE's periodic cell usable under large deformation, as the YADE backend
// does (mpmdem_rve.py): flip to a less skewed but equivalent lattice (YADE
// Cell.flipFlippable), and tile a cell thinner than 2.2 largest diameters along a lattice
// vector (every sphere copied one period further, the period doubled, contacts dropped:
// YADE's collider rebuilds them without their shear forces).
#pragma once

#include "backends/native/neighbour_list.hpp"
#include "backends/native/rve_state.hpp"

namespace mpmdem::dem::native {

inline constexpr double kTileHeight = 2.2;  // in largest sphere diameters

// True if the lattice changed (contacts' image offsets are remapped).
bool flip_cell(RveState& s, NeighbourList& nl);
// Returns the lattice vector tiled (0-2) or -1 when the cell is thick enough.
int tile_if_thin(RveState& s, NeighbourList& nl);

}  // namespace mpmdem::dem::native
