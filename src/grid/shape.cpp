#include "grid/shape.hpp"

#include "core/error.hpp"

namespace pbx {

Kernel kernel_from_name(const std::string& name) {
  if (name == "linear") return Kernel::linear;
  if (name == "ugimp") return Kernel::ugimp;
  if (name == "bspline2" || name == "quadratic_bspline") return Kernel::bspline2;
  throw InputError("unknown shape function '" + name + "' (known: linear, ugimp, bspline2)");
}

std::string kernel_name(Kernel k) {
  switch (k) {
    case Kernel::linear:
      return "linear";
    case Kernel::ugimp:
      return "ugimp";
    case Kernel::bspline2:
      return "bspline2";
  }
  return "?";
}

}  // namespace pbx
