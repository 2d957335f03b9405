// A per-particle array the engine holds outside the field registry (e.g. the contact pass's
// friction memory, kept for the touching particles only and expanded for the output), written by
// the output writers after the registered fields, like one.
#pragma once

#include <string>
#include <vector>

namespace sphforge::io {

struct ParticleArray {
  std::string name;
  int components = 1;
  std::string unit = "1";
  std::vector<double> values;  ///< components per particle, particle-major
};

}  // namespace sphforge::io
