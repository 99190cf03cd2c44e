// clang-format off
// (LIGGGHTS's own layout: LIGGGHTS's Make.sh reads the ROLLING_MODEL line at the start of a line.)
/* ----------------------------------------------------------------------
   Viscous rolling resistance ("model B" of Ai et al. 2011) for LIGGGHTS 3.8.

   This header is compiled into LIGGGHTS (GPL-2.0-or-later, like the rest of
   LIGGGHTS); scripts/build-liggghts.sh copies it into LIGGGHTS's src/.

   Model (Ai, Chen, Rotter, Ooi, "Assessment of rolling resistance models in
   discrete element simulations", Powder Technology 206 (2011) 269-282, §2.2,
   model B, eq. 11):

     M_r = -mu_R * |F_n| * w_t

   with w_t the tangential part of the relative angular velocity w_i - w_j
   (the normal, torsional part is removed as rolling_friction cdt does),
   |F_n| the magnitude of the normal contact force and mu_R the per
   type-pair coefficient `coefficientRollingViscosity` (length x time: s*m
   in SI units).

   Integration. Alone, the torque relaxes w_t with the rate
   c = mu_R |F_n| / I*, 1/I* = 1/I_i + 1/I_j (I* = I_i for a wall; solid
   spheres, I = 2/5 m r^2). The explicit update w += dt M / I multiplies w_t
   by (1 - c dt), which is unstable for c dt > 2. With `exactDecay on` (the
   default) each contact applies over one step the exact solution of its own
   linear decay, w_t(t + dt) = w_t(t) exp(-c dt) (the exponential integrator
   of a linear ODE; Hochbruck & Ostermann, "Exponential integrators",
   Acta Numerica 19 (2010) 209-286, §2), i.e. the torque
     M_r = -(I* / dt) (1 - exp(-c dt)) w_t,
   so that a contact can at most stop its relative rotation within the step
   and never reverse it. A particle has several contacts whose torques add;
   each contact's one-step decay fraction is therefore capped at 1/8, so
   that the summed fraction of up to 15 contacts stays below 2, the
   stability bound of the explicit update of a sum of linear decays
   (|1 - sum_k f_k| <= 1). The cap only acts when c dt > ln(8/7) ~ 0.13,
   i.e. when the contact would stop the rolling within about 8 steps.
   For c dt << 1 the torque equals the explicit model B torque.
   `exactDecay off` gives the plain explicit torque.
------------------------------------------------------------------------- */

#ifdef ROLLING_MODEL

ROLLING_MODEL(ROLLING_VISCOUS,viscous,5)

#else

#ifndef ROLLING_MODEL_VISCOUS_H_
#define ROLLING_MODEL_VISCOUS_H_

#include "contact_models.h"
#include "rolling_model_base.h"
#include "global_properties.h"
#include "update.h"
#include <algorithm>
#include <cmath>
#include "math_extra_liggghts.h"

namespace LIGGGHTS {
namespace ContactModels
{
  using namespace LAMMPS_NS;

  inline MatrixProperty* createCoeffRollViscosity(PropertyRegistry & registry, const char * caller, bool sanity_checks)
  {
    return MODEL_PARAMS::createPerTypePairProperty(registry, "coefficientRollingViscosity", caller, sanity_checks, 0.0);
  }

  template<>
  class RollingModel<ROLLING_VISCOUS> : public RollingModelBase {
  public:
    RollingModel(LAMMPS * lmp, IContactHistorySetup * hsetup, class ContactModelBase * c) :
        RollingModelBase(lmp, hsetup, c), coeffRollViscosity(NULL), torsion_torque(false), exact_decay(true)
    {
    }

    void registerSettings(Settings& settings)
    {
      settings.registerOnOff("torsionTorque", torsion_torque, false);
      settings.registerOnOff("exactDecay", exact_decay, true);
    }

    inline void postSettings(IContactHistorySetup *, ContactModelBase *) {}

    void connectToProperties(PropertyRegistry & registry)
    {
      registry.registerProperty("coeffRollViscosity", &createCoeffRollViscosity);
      registry.connect("coeffRollViscosity", coeffRollViscosity, "rolling_model viscous");
      if(force->cg_active())
        error->cg(FLERR,"rolling model viscous");
    }

    void surfacesIntersect(SurfacesIntersectData & sidata, ForceData & i_forces, ForceData & j_forces)
    {
      const double mu_r = coeffRollViscosity[sidata.itype][sidata.jtype];
      if(mu_r <= 0.)
        return;

      // relative angular velocity; a wall does not rotate here
      double w_rel[3];
      if(sidata.is_wall)
        vectorCopy3D(sidata.omega_i, w_rel);
      else
        vectorSubtract3D(atom->omega[sidata.i], atom->omega[sidata.j], w_rel);

      // remove the normal (torsion) part, as rolling_friction cdt does
      if(!torsion_torque)
      {
        const double w_dot_n = vectorDot3D(w_rel, sidata.en);
        w_rel[0] -= w_dot_n*sidata.en[0];
        w_rel[1] -= w_dot_n*sidata.en[1];
        w_rel[2] -= w_dot_n*sidata.en[2];
      }

      // damping coefficient of model B: mu_R |F_n|  (N m s)
      double k = mu_r*fabs(sidata.Fn);
      if(exact_decay)
      {
        // reduced moment of inertia of the pair (solid spheres) as I* = p/s: one division for all of it
        const double Ii = 0.4*sidata.mi*sidata.radi*sidata.radi;
        double p = Ii, s = 1.;
        if(!sidata.is_wall)
        {
          const double Ij = 0.4*sidata.mj*sidata.radj*sidata.radj;
          p = Ii*Ij;
          s = Ii+Ij;
        }
        const double x = k*update->dt*s/p; // c dt
        // torque coefficient f I*/dt = k f(x)/x, f = min(1 - exp(-x), 1/8). Most contacts have a small x:
        // there (1 - e^-x)/x is its Taylor series to x^6 (relative error below x^7/8! < 6e-18 for x <= 2^-6),
        // with no division and no expm1.
        double g;
        if(x <= 0.015625)
          g = 1. - x*(1./2. - x*(1./6. - x*(1./24. - x*(1./120. - x*(1./720. - x*(1./5040.))))));
        else if(x > 0.1335313926) // ln(8/7): the cap of 1/8 per contact
          g = 0.125/x;
        else
          g = -std::expm1(-x)/x;
        k *= g;
      }

      double r_torque[3];
      vectorScalarMult3D(w_rel, k, r_torque);

      i_forces.delta_torque[0] -= r_torque[0];
      i_forces.delta_torque[1] -= r_torque[1];
      i_forces.delta_torque[2] -= r_torque[2];
      j_forces.delta_torque[0] += r_torque[0];
      j_forces.delta_torque[1] += r_torque[1];
      j_forces.delta_torque[2] += r_torque[2];
    }

    void beginPass(SurfacesIntersectData&, ForceData&, ForceData&){}
    void endPass(SurfacesIntersectData&, ForceData&, ForceData&){}
    void surfacesClose(SurfacesCloseData&, ForceData&, ForceData&){}

  private:
    double ** coeffRollViscosity;
    bool torsion_torque;
    bool exact_decay;
  };
}
}

#endif // ROLLING_MODEL_VISCOUS_H_
#endif
