// The joint solve of a Lafortune texel's lobes and lookup table by
// variable projection (Golub and Pereyra 1973): T(v) is linear given the
// lobes, so for one channel every owned view's T is the closed-form
// least-squares factor of the current lobes (Daubert et al. 2001, eq. 4)
// inside the residual, and Levenberg-Marquardt solves for the lobes x
// (rho_d, then Cx, Cy, Cz, N per lobe) alone, differentiating through
// that projection. The paper's alternation (Section 5: lobes with T fixed,
// then T in closed form) converges linearly along the valley where T and
// the lobes trade scale; the projected problem has no such valley (the
// scale of f1 is a null direction, which the damping handles). For
// fitting/lafortune_fit.cc only.
#pragma once

#include <vector>

#include "fitting/lafortune_fit.h"

namespace clothfit {

// One sample's fixed terms in a channel's residual: the products l_x v_x,
// l_y v_y, l_z v_z, a factor on the lobe sum (max(l_z, 0), times T(v) where
// T is fixed), the value and its residual factor sqrt(w) / sigma. Shared
// by the lobe passes (lafortune_fit.cc) and the joint solve.
struct LafortuneSampleTerms {
  double xx, yy, zz, factor, measured, scale;
};

struct JointChannelResult {
  int iterations = 0;
  bool converged = false;  // Ceres' CONVERGENCE
  bool usable = false;     // a finite solution
};

// Solves channel `channel` from x (in/out, the channel layout; the lobes'
// peaks at most peak_cap, fitting/lafortune_bounds_internal.h); lut
// (in/out, T per view of the samples): views with own[v] get the
// projected factor of the solution (in [0, max_t]), the others keep their
// T.
JointChannelResult SolveJointChannel(const TexelSamples& samples,
                                     const std::vector<bool>& own, int channel,
                                     int lobes,
                                     const LafortuneFitOptions& options,
                                     double max_t, double peak_cap, double* x,
                                     std::vector<double>* lut);

// The views without an entry of their own (!own[k]) take T interpolated
// from those with one (LookupView over `views`); T = 1 when none has.
void FollowOwnedViews(const std::vector<bool>& own,
                      const std::vector<glm::dvec3>& views,
                      std::vector<glm::dvec3>* t);

// Every channel of *p and the owned views' T on the samples `on`
// (SolveJointChannel), the other views following them; twice when some
// views follow (their T refreshed between). Usable: every channel reached
// a finite solution (the others keep their start).
JointChannelResult SolveJoint(const TexelSamples& on,
                              const std::vector<bool>& own,
                              const LafortuneFitOptions& options, double max_t,
                              double peak_cap, LafortuneParams* p,
                              std::vector<glm::dvec3>* t);

// The gauge: T times f1 is unchanged when T is divided and f1 multiplied
// by the same s (rho_d by s, each lobe's C by s^(1/N)). With s the mean T
// of the owned views, per channel, the table's mean is 1; a channel whose
// lobes would leave their bounds (LobesWithinReach, rho_d <= 1 / pi)
// keeps its scale.
void NormaliseLookupTable(const std::vector<bool>& own, double peak_cap,
                          LafortuneParams* p, std::vector<glm::dvec3>* t);

// Whether a fit with these options runs the joint solve: with a lookup
// table of fitted views (has_lut_views) and more than one pass; otherwise
// both solves are the same lobe fit.
inline bool JointSolveRuns(const LafortuneFitOptions& options,
                           bool has_lut_views) {
  return has_lut_views && options.solve == LafortuneSolve::kJoint &&
         options.max_alternations > 1;
}

// One solve of FitLafortune with options.solve as given
// (fitting/lafortune_fit.cc); FitLafortune (fitting/lafortune_joint.cc)
// falls back from the joint solve to the alternation where the joint
// optimum is not plausible.
LafortuneFitResult FitLafortuneOnce(const TexelSamples& samples,
                                    const LafortuneFitOptions& options);

}  // namespace clothfit
