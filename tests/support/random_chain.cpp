// SPDX-License-Identifier: MIT
#include "support/random_chain.h"

#include "support/fixtures.h"

#include <cmath>
#include <string>

namespace plancheck::testing {

namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

}  // namespace

Scene random_chain_scene(std::mt19937_64& rng, bool scales) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::uniform_int_distribution<int> kind(0, 3), len(1, 5);
  Scene scene;
  Part part;
  part.name = "P";
  const Vec3 lo(u(rng), u(rng), u(rng));
  part.mesh = testing::box_mesh(lo, lo + Vec3(0.1 + std::abs(u(rng)), 0.1 + std::abs(u(rng)), 0.1));
  int param = 0;
  const int n = len(rng);
  for (int i = 0; i < n; ++i) {
    Action a;
    a.name = "A" + std::to_string(i);
    a.first_parameter = param;
    switch (kind(rng)) {
      case 0: case 1:
        a.type = ActionType::kRotate;
        a.pivot = Vec3(u(rng), u(rng), u(rng));
        a.axis = random_unit(rng);
        if (rng() % 2) a.unit_to_si = kPi / 180, a.whole_turn = 360;  // written in degrees
        break;
      case 2:
        a.type = rng() % 2 ? ActionType::kTranslateAxis : ActionType::kTranslateFree;
        a.axis = random_unit(rng);
        if (rng() % 2) a.unit_to_si = 0.001;  // written in millimetres
        if (a.type == ActionType::kTranslateFree) a.parameter_count = 3;
        break;
      case 3:
        if (!scales) {  // a rotation about the pivot drawn here instead
          a.type = ActionType::kRotate;
          a.pivot = Vec3(u(rng), u(rng), u(rng));
          a.axis = random_unit(rng);
          break;
        }
        a.type = ActionType::kScale;
        a.fixed_point = Vec3(u(rng), u(rng), u(rng));
        a.parameter_count = 3;
        break;
    }
    param += a.parameter_count;
    part.chain.push_back(static_cast<int>(scene.actions.size()));
    scene.actions.push_back(a);
  }
  part.chain_id = 0;
  scene.chains.push_back(part.chain);
  scene.parts.push_back(part);
  scene.reference_parameters.assign(static_cast<std::size_t>(param), 0.0);
  return scene;
}

}  // namespace plancheck::testing
