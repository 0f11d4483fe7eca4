#pragma once
// An abradable coating on a rigid surface (a casing): the model of Legrand, Batailly & Pierre,
// J. Comput. Nonlinear Dynam. 7(1) 011010 (2012). The coating is a layer of
// independent one-dimensional bar elements normal to the surface, of length t (the thickness) and
// face area A_e, each elastic-plastic with linear isotropic hardening (Simo & Hughes, Computational
// Inelasticity (1998), chapter 1: the 1-D return mapping), loaded in compression only (a bar has no mass and the
// blade cannot pull it). The elements tile the surface's parameter domain: n_u x n_v cells of equal
// parameter size (for the Casing surface, around the circumference x along the axis). Element e under
// a node is the cell of the node's foot point (u, v), in the surface's own frame, so a turning casing
// carries its coating.
//
// State of element e: its plastic shortening u_p (the wear: the free end has receded by u_p). With
// delta the compression of the element from its unworn free end (delta = t - g, g the node's gap to
// the surface behind the coating), the stress (compression positive) is
//     sigma = E (delta - u_p) / t                         elastic, while sigma <= sigma_y(u_p)
//     sigma_y(u_p) = sigma_Y + H u_p / t                  the current yield stress (alpha = u_p / t)
// and beyond it the return mapping gives the plastic shortening that puts sigma on the yield stress:
//     u_p' = (E delta - sigma_Y t) / (E + H),  sigma = E (H delta + sigma_Y t) / (t (E + H)).
// The element's force is A_e sigma. delta is at most t: a node at the surface (g = 0) has crushed the
// element, and the rigid surface behind it takes the rest. The plastic dissipation of an increment
// u_p -> u_p' is the work of the yield force, A_e (sigma_Y (u_p' - u_p) + H (u_p'^2 - u_p^2) / 2t);
// the elastic energy held is A_e t sigma^2 / 2E.
//
// The profile the detection sees is the surface moved towards the nodes by t - u_p of the element
// under each node (Epaphe_ContactDetection.hpp), and the enforcement (CoatingContact,
// Epaphe_CoatingContact.hpp) applies the element's force law to the penetration p of a node into
// that profile (delta = u_p + p).
#include <Kokkos_Core.hpp>
#include <Teuchos_ParameterList.hpp>
#include <string>
#include <vector>

#include "Epaphe_BSplineSurface.hpp"

namespace epaphe {

/// A coating's deck data (`Surfaces-><s>->Coating`).
struct CoatingMaterial {
  double thickness = 0;         ///< t (m); 0: the coating is absent and the surface acts rigid
  double youngsModulus = 0;     ///< E (Pa)
  double yieldStress = 0;       ///< sigma_Y (Pa); a huge value: elastic
  double hardeningModulus = 0;  ///< H (Pa), >= 0 (0: perfectly plastic)
  int elements[2] = {0, 0};     ///< n_u x n_v (around, along the axis for a Casing)
  /// The deck's Coating list (validated), with its keys' documentation.
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  /// Reads a validated Coating list; `where` names it for errors.
  static CoatingMaterial fromParameters(const Teuchos::ParameterList& pl, const std::string& where);
};

/// One element's law (its surface's t, E, sigma_Y, H and its face area A), copied by value in kernels.
struct ElementLaw {
  /// t (m), E (Pa), sigma_Y (Pa), H (Pa), A_e (m^2)
  ///@{
  double t = 0, E = 0, sY = 0, H = 0, A = 0;
  ///@}

  /// The current yield stress sigma_y(u_p) = sigma_Y + H u_p / t is not reached at penetration p
  /// beyond the worn front (compression u_p + p): the elastic branch.
  KOKKOS_INLINE_FUNCTION bool elastic(double p, double up) const { return E * p / t <= sY + H * up / t; }

  /// Stress (Pa, compression positive) at compression delta from the unworn free end, plastic
  /// shortening up: the return mapping above, without changing the state. delta is capped at t (the
  /// rigid surface behind); no contact (delta <= up) gives 0.
  KOKKOS_INLINE_FUNCTION double stress(double delta, double up) const {
    if (!(t > 0.0)) return 0.0;
    if (delta > t) delta = t;
    const double trial = E * (delta - up) / t;
    if (trial <= 0.0) return 0.0;
    if (trial <= sY + H * up / t) return trial;
    return E * (H * delta + sY * t) / (t * (E + H));
  }

  /// The plastic shortening after the element reached compression delta (capped at t) from up.
  KOKKOS_INLINE_FUNCTION double plasticShortening(double delta, double up) const {
    if (!(t > 0.0)) return 0.0;
    if (delta > t) delta = t;
    const double next = (E * delta - sY * t) / (E + H);
    return next > up ? next : up;
  }

  /// Plastic work (J) of the increment up0 -> up1 (>= up0): the yield force integrated.
  KOKKOS_INLINE_FUNCTION double dissipation(double up0, double up1) const {
    if (!(t > 0.0) || !(up1 > up0)) return 0.0;
    return A * (sY * (up1 - up0) + H * (up1 * up1 - up0 * up0) / (2.0 * t));
  }
};

/// Every coated surface's elements, concatenated; copied by value into kernels. Per surface s:
/// law(s) = {t, E, sigma_Y, H}, grid(s) = {n_u, n_v, first element} (n_u = 0: no coating).
struct CoatingViews {
  Kokkos::View<double* [4]> law;  ///< [s] t, E, sigma_Y, H of surface s's coating
  Kokkos::View<int* [3]> grid;    ///< [s] n_u, n_v, first element of surface s's coating (n_u = 0: none)
  Kokkos::View<double*> wear;     ///< [e] plastic shortening u_p (m)
  Kokkos::View<double*> area;     ///< [e] face area A_e (m^2)
  Kokkos::View<int*> surface;     ///< [e] its surface

  /// Element of surface s under the foot point (u, v) (s's own parameters), -1 without a coating.
  /// `previous`: the element the node had on s at its last projection (-1: none): it is kept while
  /// the foot point lies within 1e-6 of a cell of it, so that a node on an element boundary does not
  /// change element with round-off (it would at once wear an unworn neighbour to its depth:
  /// verification.coating-perturbed).
  KOKKOS_INLINE_FUNCTION int element(int s, const SurfaceView& S, double u, double v, int previous = -1) const {
    const int nu = grid(s, 0), nv = grid(s, 1);
    if (nu == 0) return -1;
    const double x = u / S.uMax() * nu, y = v / S.vMax() * nv;
    if (previous >= grid(s, 2) && previous < grid(s, 2) + nu * nv) {
      const int ip = (previous - grid(s, 2)) / nv, jp = (previous - grid(s, 2)) % nv;
      constexpr double slack = 1e-6;
      if (x >= ip - slack && x <= ip + 1 + slack && y >= jp - slack && y <= jp + 1 + slack) return previous;
    }
    int i = static_cast<int>(::floor(x)), j = static_cast<int>(::floor(y));
    i = i < 0 ? 0 : (i >= nu ? nu - 1 : i);
    j = j < 0 ? 0 : (j >= nv ? nv - 1 : j);
    return grid(s, 2) + i * nv + j;
  }
  /// Element e's law.
  KOKKOS_INLINE_FUNCTION ElementLaw elementLaw(int e) const {
    const int s = surface(e);
    return ElementLaw{law(s, 0), law(s, 1), law(s, 2), law(s, 3), area(e)};
  }
  /// How far surface s's profile lies in front of the surface at element e: t - u_p (0 without one).
  KOKKOS_INLINE_FUNCTION double offset(int s, int e) const { return e < 0 ? 0.0 : law(s, 0) - wear(e); }
  /// The number of elements of all coatings.
  int numElements() const { return static_cast<int>(wear.extent(0)); }
  /// True when some surface has a coating.
  bool any() const { return wear.extent(0) > 0; }
};

/// Builds the views of `materials` (one per surface; elements {0, 0}: none) on `surfaces`: the
/// element grids and each element's face area, integrated over its parameter cell (4 x 4 Gauss
/// points of |S_u x S_v|). Wear starts at 0.
CoatingViews makeCoatingViews(const std::vector<const BSplineSurface*>& surfaces,
                              const std::vector<CoatingMaterial>& materials);

/// Element centres of surface s's coating: angle about `axis` through `center` (rad, [0, 2 pi), per
/// column i) and the axial coordinate along it (m, per row j), from the cell centres S(u_i, v_j).
void coatingCentres(const BSplineSurface& surface, const CoatingMaterial& m, const double axis[3],
                    const double center[3], std::vector<double>& angle, std::vector<double>& axial);

/// Wear lobes of a coating's final profile (the definition the Python epaphe-rotor uses too): the
/// circumferential profile w_i = max_j wear(i, j); the dominant harmonic n in [1, n_u / 2] of largest
/// |W_n|, W_n = sum_i w_i exp(-2 pi I n i / n_u) (ties within 1e-9: the smallest; 0 when every
/// |W_n| < 1e-12 n_u max(w)), and the angles where it peaks; the lobe count: circular runs of columns
/// with w_i > max(w) / 2 (all of them: one), each at its first column of largest w.
struct WearLobes {
  ///@{
  int count = 0, dominantOrder = 0;  ///< the lobe count; the dominant harmonic n (0: none)
  ///@}
  double maxWear = 0;  ///< max(w) (m)
  ///@{
  std::vector<double> angles, harmonicAngles;  ///< rad: the lobes' angles, the dominant harmonic's peaks
  ///@}
};
/// The wear lobes of a coating's final profile (see WearLobes): `angle` per column (rad), `wear` the
/// nu x nv elements' wear, row-major by column i (m).
WearLobes wearLobes(const std::vector<double>& angle, const double* wear, int nu, int nv);

}  // namespace epaphe
