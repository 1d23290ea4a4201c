// Bit-for-bit comparison of two runs, for the tests that promise that two paths (a batched
// kernel and simulate(), a scene and its shorthand) give the same numbers.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/common/run_record.hpp"

namespace impactid::testing {

/// Equal bits, or both NaN (a NaN's sign and payload are not results).
inline bool same(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) ||
         (std::isnan(a) && std::isnan(b));
}

inline void expect_same_samples(const std::vector<double>& got, const std::vector<double>& want,
                                const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < want.size(); ++i) {
    ASSERT_TRUE(same(got[i], want[i]))
        << what << " sample " << i + 1 << ": " << got[i] << " vs " << want[i];
  }
}

/// Every field of the summaries but the wall time, and every column of the traces.
inline void expect_same_run(const RunSummary& got, const ContactTrace& got_trace,
                            const RunSummary& want, const ContactTrace& want_trace,
                            const std::string& name) {
  EXPECT_EQ(got.status, want.status) << name;
  EXPECT_EQ(got.message, want.message) << name;
  EXPECT_EQ(got.planned_steps, want.planned_steps) << name;
  EXPECT_EQ(got.steps, want.steps) << name;
  EXPECT_EQ(got.skipped_steps, want.skipped_steps) << name;
  EXPECT_TRUE(same(got.dt, want.dt)) << name;
  EXPECT_TRUE(same(got.initial_energy, want.initial_energy)) << name;
  EXPECT_TRUE(same(got.final_energy, want.final_energy))
      << name << ": " << got.final_energy << " vs " << want.final_energy;
  EXPECT_TRUE(same(got.max_penetration, want.max_penetration))
      << name << ": " << got.max_penetration << " vs " << want.max_penetration;
  expect_same_samples(got_trace.pressure, want_trace.pressure, name + " pressure");
  expect_same_samples(got_trace.velocity, want_trace.velocity, name + " velocity");
  expect_same_samples(got_trace.displacement, want_trace.displacement, name + " displacement");
  expect_same_samples(got_trace.energy, want_trace.energy, name + " energy");
  expect_same_samples(got_trace.far_pressure, want_trace.far_pressure, name + " far pressure");
  ASSERT_EQ(got_trace.contact_pressure.size(), want_trace.contact_pressure.size()) << name;
  for (std::size_t c = 0; c < want_trace.contact_pressure.size(); ++c) {
    const std::string contact = name + " contact " + std::to_string(c);
    expect_same_samples(got_trace.contact_pressure[c], want_trace.contact_pressure[c],
                        contact + " pressure");
    expect_same_samples(got_trace.contact_velocity[c], want_trace.contact_velocity[c],
                        contact + " velocity");
  }
}

}  // namespace impactid::testing
