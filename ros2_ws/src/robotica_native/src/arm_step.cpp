// Compiled RK4 step of robotica_sim.arm_simulation (a manipulator's forward dynamics, book §5.7).
//
// robotica_sim/arm_simulation.py validates the input, saturates the torque and documents the
// model; this file advances (q, q') by one classical RK4 step of
//
//     q'' = ABA(q, q', tau - F(q')),   F(q') = B q' + Tc+ [q' > 0] + Tc- [q' < 0]
//
// with the torque held over the step, then stops each joint at its limits: q is clamped into
// [lower, upper] and a velocity pointing further out is zeroed (infinite limits: no stop). Every
// intermediate vector is allocated once, with the model: a step allocates no memory. B holds
// the viscous friction of the dyn table referred to the joint (G² B) plus any unmodelled
// viscous friction, Tc± the Coulomb friction (|G| Tc±).
// The model is the Pinocchio model robotica_kin.pinocchio_model builds (motor inertia as
// armature, a payload already added), serialised by Pinocchio in Python and read here; its
// joints are one-dimensional (revolute or prismatic), so q and q' have the same size. The
// interface is plain C for ctypes.

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/serialization.hpp>

#include "c_error.hpp"

#include <exception>
#include <stdexcept>
#include <string>

namespace
{

using Vector = Eigen::VectorXd;

class Arm
{
public:
  Arm(
    const char * model_text, const double * gravity, const double * viscous,
    const double * coulomb_positive, const double * coulomb_negative, const double * lower,
    const double * upper)
  {
    model_.loadFromString(model_text);
    if (model_.nq != model_.nv) {
      throw std::invalid_argument("the arm's joints must be one-dimensional (nq == nv)");
    }
    model_.gravity.linear(Eigen::Map<const Eigen::Vector3d>(gravity));
    model_.gravity.angular().setZero();
    data_ = pinocchio::Data(model_);
    const int n = model_.nv;
    viscous_ = Eigen::Map<const Vector>(viscous, n);
    coulomb_positive_ = Eigen::Map<const Vector>(coulomb_positive, n);
    coulomb_negative_ = Eigen::Map<const Vector>(coulomb_negative, n);
    lower_ = Eigen::Map<const Vector>(lower, n);
    upper_ = Eigen::Map<const Vector>(upper, n);
    for (Vector * v : {&load_, &q0_, &x_, &v1_, &v2_, &v3_, &v4_, &a1_, &a2_, &a3_, &a4_}) {
      v->resize(n);
    }
  }

  // One RK4 step of length h [s] with torque tau, in place on q and qd, then the joint stops.
  void step(double * q_out, double * qd_out, const double * tau_in, double h)
  {
    Eigen::Map<Vector> q(q_out, model_.nq);
    Eigen::Map<Vector> qd(qd_out, model_.nv);
    const Eigen::Map<const Vector> tau(tau_in, model_.nv);
    q0_ = q;
    v1_ = qd;
    acceleration(q0_, v1_, tau, a1_);
    x_ = q0_ + 0.5 * h * v1_;
    v2_ = v1_ + 0.5 * h * a1_;
    acceleration(x_, v2_, tau, a2_);
    x_ = q0_ + 0.5 * h * v2_;
    v3_ = v1_ + 0.5 * h * a2_;
    acceleration(x_, v3_, tau, a3_);
    x_ = q0_ + h * v3_;
    v4_ = v1_ + h * a3_;
    acceleration(x_, v4_, tau, a4_);
    q = q0_ + (h / 6.0) * (v1_ + 2.0 * v2_ + 2.0 * v3_ + v4_);
    qd = v1_ + (h / 6.0) * (a1_ + 2.0 * a2_ + 2.0 * a3_ + a4_);
    for (int i = 0; i < model_.nv; ++i) {
      if (q[i] < lower_[i]) {
        q[i] = lower_[i];
        qd[i] = qd[i] < 0.0 ? 0.0 : qd[i];
      } else if (q[i] > upper_[i]) {
        q[i] = upper_[i];
        qd[i] = qd[i] > 0.0 ? 0.0 : qd[i];
      }
    }
  }

private:
  // a = ABA(q, v, tau - F(v)), written into a (no allocation).
  void acceleration(
    const Vector & q, const Vector & v, const Eigen::Map<const Vector> & tau, Vector & a)
  {
    for (int i = 0; i < model_.nv; ++i) {
      const double coulomb = v[i] > 0.0 ? coulomb_positive_[i] :
        (v[i] < 0.0 ? coulomb_negative_[i] : 0.0);
      load_[i] = tau[i] - viscous_[i] * v[i] - coulomb;
    }
    a = pinocchio::aba(model_, data_, q, v, load_);
  }

  pinocchio::Model model_;
  pinocchio::Data data_;
  Vector viscous_;
  Vector coulomb_positive_;
  Vector coulomb_negative_;
  Vector lower_;
  Vector upper_;
  Vector load_;
  Vector q0_, x_, v1_, v2_, v3_, v4_, a1_, a2_, a3_, a4_;   // RK4 stages
};

}  // namespace

extern "C" {

// Read a Pinocchio model (Model::saveToString), the gravity acceleration [m/s²] in the base
// frame (3 values), the friction coefficients (n values each: viscous [N m s], Coulomb for
// q' > 0 and for q' < 0 [N m]) and the joint stops (n values each: lower and upper limit [rad |
// m], +-inf for none). Return a handle, or NULL with a message in error.
__attribute__((visibility("default")))
void * ras_arm_new(
  const char * model_text, const double * gravity, const double * viscous,
  const double * coulomb_positive, const double * coulomb_negative, const double * lower,
  const double * upper, char * error, long error_size)
{
  return new_or_report([&] {
      return new Arm(
        model_text, gravity, viscous, coulomb_positive, coulomb_negative, lower, upper);
    }, error, error_size);
}

__attribute__((visibility("default")))
void ras_arm_free(void * arm)
{
  delete static_cast<Arm *>(arm);
}

// Advance q and qd (n values each, in place) by one RK4 step of h seconds with torque tau and
// stop the joints at their limits.
// Return 0, or -1 with a message in error on a C++ exception (q and qd may then be changed).
__attribute__((visibility("default")))
long ras_arm_step(
  void * arm, double * q, double * qd, const double * tau, double h, char * error,
  long error_size)
{
  try {
    static_cast<Arm *>(arm)->step(q, qd, tau, h);
  } catch (const std::exception & e) {
    copy_message(e.what(), error, error_size);
    return -1;
  }
  return 0;
}

}  // extern "C"
