// SPDX-License-Identifier: MIT
// consumer SCENE.json [VALUE...]: checks one state (missing values: the
// reference state) and prints "verdict min_distance part_a part_b".
#include <plancheck/plancheck.h>

#include <cstdlib>
#include <iostream>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  try {
    const plancheck::Scene scene = plancheck::Scene::load(argv[1]);  // throws plancheck::Error
    const plancheck::Checker checker(scene);                          // thread-safe
    std::vector<double> state = scene.reference_state();              // plan units, as written
    for (int i = 2; i < argc && i - 2 < static_cast<int>(state.size()); ++i) state[i - 2] = std::atof(argv[i]);
    const plancheck::StateResult r = checker.check(state);
    std::cout << plancheck::verdict_name(r.verdict) << " " << r.min_distance << " " << r.part_a << " " << r.part_b
              << "\n";
    return r.verdict == plancheck::Verdict::kSafe ? 0 : 1;
  } catch (const plancheck::Error& e) {
    std::cerr << "plancheck: " << e.what() << "\n";
    return 2;
  }
}
