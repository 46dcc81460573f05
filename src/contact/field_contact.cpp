#include "contact/field_contact.hpp"

namespace pbx {

template <int D>
void weld_fields(Grid<D>& grid, int deformable, double mass_eps) {
  if (deformable < 2) return;
  const long nn = grid.nodes();
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nn; ++i) {
    double m = 0;
    int present = 0;
    Vec<D> p = Vec<D>::Zero();
    for (int f = 0; f < deformable; ++f) {
      const long k = grid.at(f, i);
      if (grid.mass[k] > mass_eps) {
        m += grid.mass[k];
        p += grid.mom[k];
        ++present;
      }
    }
    if (present < 2) continue;
    const Vec<D> vcm = p / m;
    for (int f = 0; f < deformable; ++f) {
      const long k = grid.at(f, i);
      if (grid.mass[k] > mass_eps) grid.mom[k] = grid.mass[k] * vcm;
    }
  }
}

template void weld_fields<2>(Grid<2>&, int, double);
template void weld_fields<3>(Grid<3>&, int, double);

}  // namespace pbx
