#include "study/studies/study_results.hpp"

#include <algorithm>

namespace impactid {

long StudyResults::points_done() const {
  return static_cast<long>(
      std::count_if(status.begin(), status.end(), [](int s) { return s != kStatusNotDone; }));
}

const ResultColumn* StudyResults::find_column(const std::string& name) const {
  for (const auto* columns : {&parameters, &indicators}) {
    for (const ResultColumn& c : *columns) {
      if (c.name == name) return &c;
    }
  }
  return nullptr;
}

}  // namespace impactid
