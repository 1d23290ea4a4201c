// A square grid of side × side nodes of Q1 membrane elements (stiffness E = 1 per element), one
// DOF per node, a unit lumped mass per element shared by its nodes, every node at rest in place
// and moving at v = −1: a 2D model whose M is diagonal, for the model kernels' tests
// (tests/batched_model_test.cpp) and benchmarks (bench/model_bench.cpp), which add their own
// contacts. Header-only: the two trees share it, neither links the other.
#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "core/model/model_scene.hpp"

namespace impactid::testing {

inline std::shared_ptr<Model> grid_membrane(int side) {
  const int n = side * side;
  const double ke[4][4] = {{4, -1, -2, -1}, {-1, 4, -1, -2}, {-2, -1, 4, -1}, {-1, -2, -1, 4}};
  std::vector<Eigen::Triplet<double>> k, m;
  for (int i = 0; i + 1 < side; ++i) {
    for (int j = 0; j + 1 < side; ++j) {
      const int nodes[4] = {i * side + j, i * side + j + 1, (i + 1) * side + j + 1,
                            (i + 1) * side + j};
      for (int a = 0; a < 4; ++a) {
        m.emplace_back(nodes[a], nodes[a], 0.25);
        for (int b = 0; b < 4; ++b) k.emplace_back(nodes[a], nodes[b], ke[a][b] / 6.0);
      }
    }
  }
  auto model = std::make_shared<Model>();
  model->mass.resize(n, n);
  model->mass.setFromTriplets(m.begin(), m.end());
  model->stiffness.resize(n, n);
  model->stiffness.setFromTriplets(k.begin(), k.end());
  model->initial_displacement = Eigen::VectorXd::Zero(n);
  model->initial_velocity = Eigen::VectorXd::Constant(n, -1.0);
  model->omega_bound = gershgorin_omega(model->mass, model->stiffness);
  return model;
}

}  // namespace impactid::testing
