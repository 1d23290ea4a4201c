// The level of the batched kernel file being compiled: its target, its namespace and its register
// width. core/CMakeLists.txt compiles each kernel file once per level (an object library per
// level, IMPACTID_KERNEL_LEVEL = 3 or 4), and core/batch/batch_kernels.cpp calls the level chosen
// when the program starts (core/common/kernel_level.hpp).
//
// Include it after every other header of the kernel's file and before core/batch/simd_lanes.hpp and
// core/batch/batch_lanes.hpp: from here on the file is compiled for the level (#pragma GCC target),
// while the functions of the headers above it, the standard library's and Eigen's templates
// among them, keep the baseline target wherever they are instantiated. So no function that
// another object file may also define, and the linker may pick, carries the level's
// instructions; tests/kernel_objects_test.py disassembles the level objects to hold that.
// Everything defined below goes into the level's namespace (IMPACTID_KERNEL_NAMESPACE).
#pragma once

#include <immintrin.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/common/run_record.hpp"
#include "core/common/state.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/second_order_system.hpp"
#include "core/run/simulation.hpp"

#if IMPACTID_KERNEL_LEVEL == 4
#define IMPACTID_KERNEL_NAMESPACE kernels_x86_64_v4
#define IMPACTID_KERNEL_REGISTER_LANES 8
#define IMPACTID_KERNEL_BATCH_LANES 16
#if !defined(IMPACTID_SINGLE_VERSION)
#pragma GCC target("arch=x86-64-v4")
#endif
#elif IMPACTID_KERNEL_LEVEL == 3
#define IMPACTID_KERNEL_NAMESPACE kernels_x86_64_v3
#define IMPACTID_KERNEL_REGISTER_LANES 4
#define IMPACTID_KERNEL_BATCH_LANES 8
#if !defined(IMPACTID_SINGLE_VERSION)
#pragma GCC target("arch=x86-64-v3")
#endif
#else
#error "core/batch/kernel_target.hpp: IMPACTID_KERNEL_LEVEL must be 3 or 4 (core/CMakeLists.txt)"
#endif
