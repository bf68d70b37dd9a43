// The checks of the consumer programs (consumer.cc,
// ../consumer_api/renderer.cc): failures counted, each one printed.
#pragma once

#include <cmath>
#include <iostream>
#include <string>

namespace consumer {

inline int failures = 0;

inline void Check(bool ok, const std::string& what) {
  if (!ok) {
    std::cerr << "FAIL: " << what << "\n";
    ++failures;
  }
}

inline bool Near(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::abs(b) + 1e-300;
}

}  // namespace consumer
