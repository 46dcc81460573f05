#pragma once
// The material plug-in interface. A material updates the stress of a whole batch of particles
// (all particles of that material) in one call: one virtual call per material per step, never one
// per particle. History variables live in the material's own storage (MaterialState::history),
// `history_size()` doubles per particle, addressed by the particle's slot in the batch.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/tensor.hpp"

namespace pbx {

class ParamTable;

// Conditions a material is built for: runs are isothermal at `temperature`.
struct MaterialContext {
  double temperature = 293.0;  // K
  std::string name;            // the deck's name for this material (for error messages)
};

// Views into the particle arrays for one material's batch. Arrays are indexed by particle index
// (index[k]); history is indexed by batch position k: history + k * history_size().
template <int D>
struct MaterialBatch {
  std::span<const std::uint32_t> index;
  const Mat<D>* L = nullptr;        // velocity gradient over the step, 1/s
  const Mat<D>* F = nullptr;        // deformation gradient at the end of the step
  const double* mass = nullptr;     // physical (unscaled) mass
  const double* volume = nullptr;   // current volume (end of step)
  const double* volume0 = nullptr;  // reference volume
  Sym3* stress = nullptr;           // Cauchy stress, in: start of step, out: end of step
  double* history = nullptr;
  double dt = 0;  // s
};

struct MaterialStepResult {
  double dissipated = 0;      // J (per unit depth in 2D): plastic + viscous work this step
  double stress_work = 0;     // J: sum V (sigma_n + sigma_n+1)/2 : D dt
  double max_wave_speed = 0;  // m/s: max over the batch of sqrt(M_tangent / rho), M = K + 4G/3
  double max_wave_speed2() const { return max_wave_speed * max_wave_speed; }
};

template <int D>
class Material {
 public:
  virtual ~Material() = default;
  virtual std::string model() const = 0;
  // Stress-free density at the run temperature, kg/m^3 (particle masses are built from it).
  virtual double density() const = 0;
  // Longitudinal wave speed of the unstressed material, m/s (first time step).
  virtual double initial_wave_speed() const = 0;
  virtual int history_size() const { return 0; }
  virtual std::vector<std::string> history_names() const { return {}; }
  virtual void init_history(double* /*h*/) const {}
  // Equivalent plastic strain stored in one particle's history (0 if the law has none).
  virtual double plastic_strain(const double* /*h*/) const { return 0.0; }
  virtual MaterialStepResult update(const MaterialBatch<D>& batch) const = 0;
  // Why the law cannot give a finite stress at volume ratio J (empty: no known reason); read
  // only to word the error once a non-finite stress has stopped the run.
  virtual std::string failure_reason(double /*J*/) const { return {}; }
};

// Stress power of one particle over a step by the trapezoidal rule: V (s0 + s1)/2 : D dt.
inline double stress_work(const Sym3& s0, const Sym3& s1, const Sym3& Ddt, double volume) {
  return 0.5 * volume * (s0 + s1).ddot(Ddt);
}

// Builds the material described by deck table `t` (its `model` key picks the law).
template <int D>
std::unique_ptr<Material<D>> make_material(const ParamTable& t, const MaterialContext& ctx);

// Names of every registered model, built in or registered (for error messages and docs).
std::vector<std::string> material_models();

// A model's factory: reads the model's keys from its deck table (refusing any it does not take,
// ParamTable::fail naming the key) and builds the law for the run's conditions.
template <int D>
using MaterialFactory = std::function<std::unique_ptr<Material<D>>(const ParamTable&, const MaterialContext&)>;

// Adds a model under `name` (lower-case letters, digits, '_'), for both the built-in ones' route
// and a program's own laws (docs/extending.md): one call, before the decks that use it are read.
// A name already taken is an InputError.
template <int D>
void register_material(const std::string& name, MaterialFactory<D> factory);

}  // namespace pbx
