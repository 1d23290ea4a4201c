// The scalar step's fused multiply-adds, and the machines they are fast on.
//
// The implicit step (core/implicit_integrator.cpp, core/tridiagonal.cpp) writes a multiply
// whose product is only added as std::fma: one rounding instead of two, and a recurrence of one
// instruction (4 cycles) instead of a multiply and an add (6). The batched kernel
// (core/batched_simulation.cpp) fuses exactly the same operations, so that its lanes equal the
// scalar path bit for bit. std::fma is correctly rounded, so the bits are the same on every
// machine; only its speed differs: one instruction where the processor has FMA3 (x86-64-v3:
// every x86-64 processor since 2013-2015), a C library routine elsewhere.
//
// The project builds for baseline x86-64, where std::fma is a call. Functions marked
// IMPACTID_FMA_VERSIONS are compiled a second time for x86-64-v3, and the loader picks that
// version on a processor that has it (GCC target_clones). Unmarked, the scalar HHT run took 2.6
// times as long (bench: BM_Run/3, 1.56 -> 4.0 ms).
#pragma once

#define IMPACTID_FMA_VERSIONS __attribute__((target_clones("arch=x86-64-v3", "default")))
