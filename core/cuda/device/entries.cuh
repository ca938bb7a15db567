// The kernels' extern "C" entry points: one per dimension (MF_ENTRY2), per scheme of the
// forces and rates (MF_SCHEMES) and, with MF_LANES_EACH (sph_consts.h), per lane count; and
// the launch bounds of the fluid-only schemes (MF_FLUID_BLOCKS). Twin: the table of kernel
// families in src/backend/cuda/kernels.rs, which names, loads and picks the entries.
#pragma once
#include "sph_consts.h"

// The schemes of the forces and rates kernels, for one lane count L: ENTRY(entry name, DIM,
// SOLIDS, EXTRAS, L) for `name_L_{2,3}d` (with solids), `name_fluid_L_{2,3}d` (fluid-only)
// and `name_lean_L_{2,3}d` (fluid-only without the optional terms: params::lean_scheme).
#define MF_SCHEMES(ENTRY, name, L)                       \
    ENTRY(name##_##L##_2d, 2, true, true, L)             \
    ENTRY(name##_##L##_3d, 3, true, true, L)             \
    ENTRY(name##_fluid_##L##_2d, 2, false, true, L)      \
    ENTRY(name##_fluid_##L##_3d, 3, false, true, L)      \
    ENTRY(name##_lean_##L##_2d, 2, false, false, L)      \
    ENTRY(name##_lean_##L##_3d, 3, false, false, L)

// Blocks of MF_BLOCK per SM that the fluid-only forces, rates and fused kernels are bounded
// to (4: 64 registers; 3 was slower, docs/reference/performance.md).
#ifndef MF_FLUID_BLOCKS
#define MF_FLUID_BLOCKS 4
#endif

#define MF_ENTRY2(name, params, args) \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK) name##_2d params { name##_body<2> args; } \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK) name##_3d params { name##_body<3> args; }
