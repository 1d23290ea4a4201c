#include "study/plan/plan.hpp"

namespace impactid {

const char* to_string(StudyKind kind) {
  switch (kind) {
    case StudyKind::grid:
      return "grid";
    case StudyKind::list:
      return "list";
    case StudyKind::optimize:
      return "optimize";
    case StudyKind::spectral:
      return "spectral";
    case StudyKind::work_precision:
      return "work-precision";
  }
  return "unknown";
}

}  // namespace impactid
