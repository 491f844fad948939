// SPDX-License-Identifier: MIT
// The plancheck command line (contract: README "Command line").
#include <iostream>

int main() {
  std::cerr << "plancheck: not yet built\n";
  return 2;
}
