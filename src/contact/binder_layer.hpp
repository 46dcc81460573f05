#pragma once
// The binder_layer contact law: a binder layer thinner than a cell between two grain fields,
// represented as a linear spring interface (an imperfect interface, Nairn 2007/2013) whose
// stiffnesses per unit area are those of the layer itself,
//   D_n = M_b / t,   D_t = G_b / t      (Pa/m; t = layer thickness),
// with M_b, G_b the binder's secant constrained and shear moduli at the run temperature: the
// binder material of the deck is driven through uniaxial strain and simple shear at a constant
// rate, and sigma(t)/eps(t) is exactly the secant (1/t) int_0^t E(s) ds of its relaxation
// modulus (quasi-elastic, exact for a jump that grows linearly in time). docs/theory/contact.md
// states the node law (field_contact.cpp) and its verification.
#include <string>
#include <vector>

#include "materials/material.hpp"

namespace pbx {

class ParamTable;

struct LayerLaw {
  // The law's table against time: with a binder, its secant moduli M_b(t_k), G_b(t_k) in Pa (the
  // node divides by the local layer thickness: each bonded particle carries 1/t of its contact);
  // with normal_stiffness/shear_stiffness, D_n, D_t in Pa/m (the particles then carry 1).
  // One entry = constant.
  std::vector<double> time, normal, shear;
  double friction = 0;      // Coulomb coefficient: the shear cap on the layer (Eq. 7, S_a = 0) and
                            // the law where the layer does not act
  double thickness = 0;     // t, m: one thickness for every contact (0: from the coats, or stiffnesses given)
  bool from_coats = false;  // t of a contact = coat_i + coat_j of its two grains (packed specimens)
  double coat_scale = 1.0;  // t = coat_scale (coat_i + coat_j) with from_coats
  double closure = 1.0;     // the layer is squeezed out when the normal closure exceeds closure * t
  bool shear_cap = true;    // layer shear traction <= friction x compressive normal traction (Eq. 7)
  // Film flow (issue 23; a calibration, not the paper's law): the layer's compressive normal
  // traction is capped at flow_stress (Pa), or at flow_factor x the binder's current secant shear
  // modulus G_b (the one the shear spring uses), so the cap follows the binder's temperature and
  // rate: a film extruded between two grains flows at a pressure set by the binder's shear
  // resistance (Prandtl's squeeze of a plastic layer, p ~ tau (a / h)). A flowing layer is never
  // squeezed out to Coulomb contact: past the cap the grains pass into each other at that
  // traction, standing for binder extruded into the pores and the contact zone crushing.
  // 0 = no flow (the default: the paper's model).
  double flow_stress = 0;
  double flow_factor = 0;
  bool flows() const { return flow_stress > 0.0 || flow_factor > 0.0; }
  // the cap on the compressive normal traction now, Pa (after at_time)
  double flow_cap() const { return flow_stress > 0.0 ? flow_stress : flow_factor * kt; }
  // How deep into each body from a touching particle its particles are bonded, m (0: automatic,
  // the larger of two cells and the deepest closure the layer holds, closure x the thickest t,
  // plus one cell). A node is a spring only where most of each side's mass is bonded: as the
  // bodies close by c, the nodes they share hold particles up to about c + one cell deep, and with
  // a shallower zone the layer turned to Coulomb contact (a layered column closed by 2.2 cells at
  // 5 um cells read -45 % compliance with a zone of two cells, -0.6 % with three).
  double bond_depth = 0;
  double bond_gap = 0;                 // grains whose particles come this close (beyond touching) are bonded, m
  bool bond_within_thickness = false;  // bond_gap = "thickness": bonded where the gap is below the pair's t
  // film = "integrated": each contact (a pair of bodies) gets the stiffness of its whole film,
  // M_b int dA / (t + g) over the particles of one side whose gap g to the other body is below
  // film_extent x t (the cores' surfaces diverge away from the contact point, so the film
  // thickens), spread over the particles within one cell of the other body, whose nodes the grid
  // lets the two sides share: the spring's total no longer depends on how wide that band is.
  bool integrated = false;
  // film = "bonds" (not the paper decks' law; no film flow, one process, 2-D): the same
  // film, found as with "integrated", carried by springs between particle pairs instead of at the
  // nodes: every particle facing the other body within film_extent x t is tied to its nearest
  // particle there by k_n = M_b a / (2 (t + g)), k_t = G_b a / (2 (t + g)) (a = spacing^(D-1), g the
  // local gap; both sides tie, hence the half) along the pair's reference direction. Uncapped the
  // springs are the gradient of one energy, so they can make none; where both sides are bonded the node leaves
  // the two fields alone and the pairs carry the film (Coulomb elsewhere, and once squeezed out).
  // The shear cap (Eq. 7) applies to each pair as at a node (bond_force, law_binder_layer.hpp).
  // The binder particles in a pair's gap join the nearer grain's field (setup_binder_layers): the
  // springs are that binder. Implies integrated.
  bool bonds = false;
  // gap_binder = "join": the binder particles lying between two bonded grains (within a particle
  // spacing of a facing pair's segment) join the nearer grain's field, so that the film is counted
  // once, by the springs. The default with film = "bonds"; an option with "integrated", whose
  // default ("free") leaves them a phase of their own, met by both grains through contact, which
  // counts the film a second time (docs/theory/paper_study.md, "Where the density trend comes from").
  bool join_gap_binder = false;
  double film_extent = 4.0;
  std::string binder;    // material whose moduli make D_n, D_t ("" when given directly)
  double load_time = 0;  // s: secant over this fixed time; 0 = over the elapsed run time
  // Current values (at_time): multiplied by the node's mean 1/t, the stiffnesses per unit area.
  double kn = 0, kt = 0;

  // Sets kn, kt to the table's values at time t (linear interpolation; beyond its last time the
  // last value, which build_scene puts past the run's end time).
  void at_time(double t);
};

// Reads the law's own keys from a [[contact.pair]] table with law = "binder_layer": friction
// (required), shear_cap ("coulomb" or "none"), then either normal_stiffness and shear_stiffness
// (Pa/m), or binder, thickness (a length, or "coats" with coat_scale), load_time ("elapsed" by
// default) and closure (1); bond_gap (a length, 0 by default, or "thickness"); bond_depth (a length,
// automatic by default); film ("uniform" or "integrated")
// and film_extent (4, a multiple of t). The binder moduli are filled
// in later by layer_moduli (they need the material and the run's temperature and duration).
LayerLaw read_layer_law(const ParamTable& t);

// Fills law.time/normal/shear from the binder material at the run's temperature: secant moduli
// over [0, t] for t up to end_time (load_time = "elapsed"), or at the fixed load time.
void layer_moduli(LayerLaw& law, const Material<3>& binder, double end_time, const ParamTable& where);

}  // namespace pbx
