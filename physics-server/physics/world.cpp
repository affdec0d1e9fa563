// The ODE world of one run. See world.h (interface), module_library.h (how a
// module type is described) and servo_model.h (the servo and how it is coupled
// to ODE).
//
// Determinism: ODE's random generator (QuickStep reorders constraints with it)
// is seeded with WorldConfig::seed and its state is saved/restored around every
// step, so several Worlds in one thread do not disturb each other. Collisions
// go through a simple space (geoms in creation order), contacts are created in
// the order the space reports them. No wall clock anywhere.
//
// No allocation in step(): the contact-geometry buffer is a member array; the
// contact joint group is warmed up in the constructor (its arenas are kept
// when it is emptied) and ODE's stepper reserves at least kStepReserveBytes,
// kept between steps. ODE allocates its stepping context in the first step;
// after that nothing is allocated unless a step needs more contacts or
// working memory than reserved (tested: physics_test StepDoesNotAllocate).
//
// Solver: QuickStep, WorldConfig::solver_iterations (default 30). Measured
// (tests/physics-server/physics, physics_bench), for 10 / 20 / 30 / 40 / 60 iterations:
//  * largest docking-joint stretch of an 8-module chain hanging from its head,
//    swinging limp onto the joint stops: 0.42 / 0.45 / 0.26 / 0.17 / 0.10 mm
//    (powered and sagging: 0.36 / 0.14 / 0.11 / 0.07 / 0.04 mm); while
//    crawling: 0.17 / 0.07 / 0.07 / 0.06 / 0.03 mm;
//  * a servo holding a module at 45 degrees against gravity jitters by
//    0.44 / 0.21 / 0.12 / 0.07 / 0.03 degrees peak to peak. That is solver
//    noise (the unconverged iteration, reordered at random by ODE each step):
//    dWorldStep (exact LCP) gives 0.000, at 3-4x the cost for 8 modules;
//  * the 10 s crawl distance varies by +-10% with no trend (mildly chaotic);
//  * cost grows about linearly: ~2 us per iteration for 8 modules.
// 30 keeps the jitter under one potentiometer count (0.18 degrees) at about
// 70 us per step for 8 modules. Global ERP/CFM 0.2 / 1e-9 (stiff joints; a
// softer CFM up to 1e-5 changed nothing measurable); contacts use their
// Material's soft ERP/CFM.
#include "physics/world.h"

#include <ode/ode.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>

#include "environment/environment_geoms.h"
#include "environment/pipe_wall_probe.h"
#include "model/module_def.h"
#include "physics/contact_force_log.h"
#include "physics/sensors/sensors.h"
#include "physics/wheels/wheel_contacts.h"

namespace chainsim {

namespace {

constexpr int kMaxContactsPerPair = 8;
constexpr double kMotorFMax = 10.0;   // N m; far above any servo torque (stall 0.058 N m)
constexpr double kPi = 3.14159265358979323846;
constexpr unsigned kStepReserveBytes = 4u << 20;  // ODE stepper working memory, reserved
constexpr int kWarmContactsPerGeom = 8;           // contact joints pre-allocated per geom
constexpr double kSurfaceLayer = 1e-4;            // m, ODE's allowed contact penetration

Eigen::Isometry3d to_iso(const Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = p.orientation.normalized().toRotationMatrix();
  t.translation() = p.position;
  return t;
}

Eigen::Isometry3d body_iso(dBodyID b) {
  const dReal* p = dBodyGetPosition(b);
  const dReal* q = dBodyGetQuaternion(b);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  t.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return t;
}

void ode_init_once() {
  static std::once_flag flag;
  std::call_once(flag, [] { dInitODE2(0); });
  dAllocateODEDataForThread(dAllocateMaskAll);
}

}  // namespace

struct World::Impl {
  struct Body {
    dBodyID id = nullptr;
    dGeomID geom = nullptr;
    int module = -1;
    std::string name;
    bool touched = false;      // had a contact in the last step
  };
  // a firmware-driven actuator: rotary servo, linear servo, screw drive or
  // DC motor (kind Screw: driven alike, -1..1; `hinge` set)
  struct Servo {
    ServoKind kind = ServoKind::Rotary;
    int module = -1;
    dJointID hinge = nullptr;  // Rotary, DC motor: the hinge; Linear: the slider
    // Rotary: one-axis angular motor realising the servo torque; Linear, Screw:
    // one-axis linear motor realising the force law's implicit part
    dJointID motor = nullptr;
    ServoModel model;
    double lo = 0, hi = 0;     // set-point range: rad, m or -1..1
    bool enabled = true;
    int follows = -1;          // global servo index whose set-point this one copies
    // Linear, Screw (force laws in module_library.h)
    dBodyID body = nullptr;    // Screw: the body pushed
    Eigen::Vector3d dir = Eigen::Vector3d::UnitX();  // Screw: drive axis, body frame, unit
    double fmax = 0, l0 = 0, v_free = 0, stall_a = 0;
    double cmd = 0;            // set-point: m (Linear) or -1..1 (Screw)
    bool on = false;           // driven during the last step
    double law_damping = 0, law_rate = 0, law_force = 0;  // this step: F = law_force + D (v* - v')
    double force = 0;          // force of the last step, N
    double i_motor = 0, i_f = 0;   // motor current (signed), its RC-filtered magnitude
  };
  struct Module {
    std::string type;
    int body0 = 0, nbody = 0;
    std::vector<int> driven;   // global servo indices firmware drives (servo s = driven[s])
    std::vector<int> all;      // all global servo indices of the module
    bool powered = true;
    int n_adc = 0;
    int adc_servo[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    std::vector<std::pair<int, int>> touch;  // (global body, input bit)
    int front_body = 0, back_body = 0;       // global body indices
    Eigen::Isometry3d front_in_body, back_in_body;  // face frames in their bodies' frames
  };

  WorldConfig cfg;
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  std::unique_ptr<EnvironmentGeoms> env;   // destroyed after the space (its triangle data)
  std::vector<Material> env_materials;      // environment surface index -> contact with a module
  dJointGroupID contact_group = nullptr;
  unsigned long rand_seed = 0;
  int64_t time_us = 0;
  double h = 0;
  double filter_e = 0;   // e^(-h/tau_f) of the linear servo / screw drive current filter
  int contact_count = 0;

  std::vector<Body> bodies;
  std::vector<Servo> servos;
  std::vector<Module> modules;
  Sensors sensors;   // accelerometers, wheel encoders, joint friction (sensors.h)
  std::unique_ptr<WallProbe> wall_probe;   // where wheel arms meet the wall
  WheelContacts wheels;                    // wheel sets (wheel_contacts.h)
  ContactForceLog force_log;               // WorldConfig::log_contact_forces
  dContactGeom contact_buf[kMaxContactsPerPair];

  static void near_callback(void* data, dGeomID a, dGeomID b) {
    static_cast<Impl*>(data)->collide_pair(a, b);
  }

  void collide_pair(dGeomID a, dGeomID b) {
    const intptr_t ia = reinterpret_cast<intptr_t>(dGeomGetData(a));
    const intptr_t ib = reinterpret_cast<intptr_t>(dGeomGetData(b));
    // > 0: 1 + body index; <= 0: an environment geom (EnvironmentGeoms::surface_tag)
    if (ia <= 0 && ib <= 0) return;  // environment vs environment
    const intptr_t env_tag = ia <= 0 ? ia : ib;
    const Material* mat = env_tag < 0 ? &env_materials[EnvironmentGeoms::surface_index(env_tag)]
                                      : &cfg.ground;
    if (ia > 0 && ib > 0) {
      const Body& ba = bodies[ia - 1];
      const Body& bb = bodies[ib - 1];
      if (ba.module == bb.module) return;                              // no self-collision
      if (dAreConnectedExcluding(ba.id, bb.id, dJointTypeContact)) return;  // docked pair
      mat = &cfg.module_contact;
    }
    const int n = dCollide(a, b, kMaxContactsPerPair, contact_buf, sizeof(dContactGeom));
    if (n <= 0) return;
    if (ia > 0) bodies[ia - 1].touched = true;
    if (ib > 0) bodies[ib - 1].touched = true;
    for (int k = 0; k < n; ++k) {
      dContact c;
      c.geom = contact_buf[k];
      c.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      c.surface.mu = mat->mu;
      c.surface.mu2 = 0;
      c.surface.rho = c.surface.rho2 = c.surface.rhoN = 0;
      c.surface.bounce = 0;
      c.surface.bounce_vel = 0;
      if (mat->bounce > 0) {
        c.surface.mode |= dContactBounce;
        c.surface.bounce = mat->bounce;
        c.surface.bounce_vel = 0.01;
      }
      c.surface.soft_erp = mat->soft_erp;
      c.surface.soft_cfm = mat->soft_cfm;
      c.surface.motion1 = c.surface.motion2 = c.surface.motionN = 0;
      c.surface.slip1 = c.surface.slip2 = 0;
      friction_direction(c);
      dJointID j = dJointCreateContact(world, contact_group, &c);
      dJointAttach(j, dGeomGetBody(c.geom.g1), dGeomGetBody(c.geom.g2));
      ++contact_count;
      if (force_log.enabled()) {
        const intptr_t t1 = reinterpret_cast<intptr_t>(dGeomGetData(c.geom.g1));
        const intptr_t t2 = reinterpret_cast<intptr_t>(dGeomGetData(c.geom.g2));
        force_log.add(j, t1 > 0 ? static_cast<int>(t1 - 1) : -1,
                      t2 > 0 ? static_cast<int>(t2 - 1) : -1, c.geom.normal);
      }
    }
  }

  // ODE's Coulomb friction is a pyramid: two directions in the contact
  // plane, each limited to mu N, so something sliding at 45 degrees to them
  // meets sqrt(2) times mu N. Left to ODE, the directions come from the normal
  // alone (dPlaneSpace): on a floor the world's x and y, so a gait that slides
  // sideways went elsewhere when the chain started at another heading (the
  // lateral shift: 1.36 m across at 0 degrees, 0.96 m across and 0.86 m along
  // at 45). Here the pyramid is turned about the normal so that one of its
  // directions lies along the sliding velocity at the contact, which makes
  // the friction against the motion exactly mu N, whatever the heading.
  // Slow contacts keep ODE's own directions and the turn grows smoothly with
  // the sliding speed (weight v^2 / (v^2 + kFrictionTurnSpeed^2)): turned
  // sharply at mm/s speeds, a contact that a servo presses while it creeps
  // chattered with QuickStep's 30 iterations (a touch cover read contact in
  // 44 % of the steps instead of all of them; fine at 300 iterations).
  static constexpr double kFrictionTurnSpeed = 0.01;  // m/s
  static void friction_direction(dContact& c) {
    const dReal* n = c.geom.normal;
    dVector3 pp, qq;
    dPlaneSpace(n, pp, qq);
    const dBodyID b1 = dGeomGetBody(c.geom.g1), b2 = dGeomGetBody(c.geom.g2);
    dVector3 v1 = {0, 0, 0}, v2 = {0, 0, 0};
    if (b1) dBodyGetPointVel(b1, c.geom.pos[0], c.geom.pos[1], c.geom.pos[2], v1);
    if (b2) dBodyGetPointVel(b2, c.geom.pos[0], c.geom.pos[1], c.geom.pos[2], v2);
    const Eigen::Vector3d p(pp[0], pp[1], pp[2]), q(qq[0], qq[1], qq[2]);
    const Eigen::Vector3d v(v1[0] - v2[0], v1[1] - v2[1], v1[2] - v2[2]);
    const double vp = v.dot(p), vq = v.dot(q), s2 = vp * vp + vq * vq;
    // the smallest turn of (p, q) that puts p or q along the sliding, scaled
    // by the weight; a quarter turn maps the pyramid onto itself
    const double a = std::atan2(vq, vp);
    const double turn = (a - std::round(a / (M_PI / 2)) * (M_PI / 2)) *
                        (s2 / (s2 + kFrictionTurnSpeed * kFrictionTurnSpeed));
    // (Between the two ends the turn jumps from +w 45 to -w 45 degrees where
    // the sliding crosses a diagonal of the pyramid: no continuous blend of
    // "turn with the sliding" and "do not turn" exists on a quarter-turn
    // circle. The jump is 0 at both ends and largest, 45 degrees, at 1 cm/s.)
    Eigen::Vector3d d = std::cos(turn) * p + std::sin(turn) * q;
    d.normalize();  // p, q are unit for a unit normal; the pipe geoms write their own normals
    c.surface.mode |= dContactFDir1;
    c.fdir1[0] = d.x();
    c.fdir1[1] = d.y();
    c.fdir1[2] = d.z();
    c.fdir1[3] = 0;
  }

  void build();
  void add_module(int index, const ModuleDef& def, const Eigen::Isometry3d& frame);
  void add_force_actuator(int index, Module& md, const ModuleDef& def, const ActuatorDef& ad,
                          const Eigen::Isometry3d& frame, const std::vector<dJointID>& joints);
  void begin_force_actuator(Servo& s);
  void end_force_actuator(Servo& s);
  uint16_t adc_counts(const Servo& s) const;
  double actuator_rate(const Servo& s) const;

  const Module& mod(int m) const {
    if (m < 0 || m >= static_cast<int>(modules.size()))
      throw std::out_of_range("module index " + std::to_string(m) + " out of range");
    return modules[m];
  }
  int servo_index(int m, int s) const {
    const Module& md = mod(m);
    if (s < 0 || s >= static_cast<int>(md.driven.size()))
      throw std::out_of_range("servo " + std::to_string(s) + " of module " + std::to_string(m) +
                              " out of range");
    return md.driven[s];
  }
  int body_index(int m, int b) const {
    const Module& md = mod(m);
    if (b < 0 || b >= md.nbody)
      throw std::out_of_range("body " + std::to_string(b) + " of module " + std::to_string(m) +
                              " out of range");
    return md.body0 + b;
  }
};

void World::Impl::add_module(int index, const ModuleDef& def, const Eigen::Isometry3d& frame) {
  Module md;
  md.type = def.type;
  md.body0 = static_cast<int>(bodies.size());
  md.nbody = static_cast<int>(def.bodies.size());

  for (const BodyDef& bd : def.bodies) {
    const Eigen::Isometry3d t = frame * to_iso(bd.pose);
    const Eigen::Quaterniond q(t.linear());
    Body b;
    b.module = index;
    b.name = bd.name;
    b.id = dBodyCreate(world);
    dBodySetPosition(b.id, t.translation().x(), t.translation().y(), t.translation().z());
    const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
    dBodySetQuaternion(b.id, dq);
    dMass m;
    switch (bd.shape) {
      case Shape::Capsule:
        dMassSetCapsuleTotal(&m, bd.mass_kg, 3, bd.radius_m, bd.length_m);
        b.geom = dCreateCapsule(space, bd.radius_m, bd.length_m);
        break;
      case Shape::Cylinder:
        dMassSetCylinderTotal(&m, bd.mass_kg, 3, bd.radius_m, bd.length_m);
        b.geom = dCreateCylinder(space, bd.radius_m, bd.length_m);
        break;
      case Shape::Box:
        dMassSetBoxTotal(&m, bd.mass_kg, bd.box_m.x(), bd.box_m.y(), bd.box_m.z());
        b.geom = dCreateBox(space, bd.box_m.x(), bd.box_m.y(), bd.box_m.z());
        break;
      case Shape::Sphere:
        dMassSetSphereTotal(&m, bd.mass_kg, bd.radius_m);
        b.geom = dCreateSphere(space, bd.radius_m);
        break;
    }
    dBodySetMass(b.id, &m);
    if (bd.collides) {
      dGeomSetBody(b.geom, b.id);
      // 1-based global body index; 0 marks the environment
      dGeomSetData(b.geom, reinterpret_cast<void*>(static_cast<intptr_t>(bodies.size() + 1)));
    } else {  // the shape gave the mass; no contacts
      dGeomDestroy(b.geom);
      b.geom = nullptr;
    }
    bodies.push_back(b);
  }

  std::vector<dJointID> joints;
  for (const JointDef& jd : def.joints) {
    dBodyID parent = bodies[md.body0 + jd.parent].id;
    dBodyID child = bodies[md.body0 + jd.child].id;
    const Eigen::Vector3d anchor = frame * jd.anchor_m;
    const Eigen::Vector3d axis = frame.linear() * jd.axis.normalized();
    dJointID j = nullptr;
    // body1 = child, body2 = parent: ODE's angle/position is body1 relative to body2
    switch (jd.type) {
      case JointType::Hinge:
        j = dJointCreateHinge(world, nullptr);
        dJointAttach(j, child, parent);
        dJointSetHingeAnchor(j, anchor.x(), anchor.y(), anchor.z());
        dJointSetHingeAxis(j, axis.x(), axis.y(), axis.z());
        if (std::isfinite(jd.lo)) dJointSetHingeParam(j, dParamLoStop, jd.lo);
        if (std::isfinite(jd.hi)) dJointSetHingeParam(j, dParamHiStop, jd.hi);
        break;
      case JointType::Slider:
        j = dJointCreateSlider(world, nullptr);
        dJointAttach(j, child, parent);
        dJointSetSliderAxis(j, axis.x(), axis.y(), axis.z());
        if (std::isfinite(jd.lo)) dJointSetSliderParam(j, dParamLoStop, jd.lo);
        if (std::isfinite(jd.hi)) dJointSetSliderParam(j, dParamHiStop, jd.hi);
        break;
      case JointType::Fixed:
        j = dJointCreateFixed(world, nullptr);
        dJointAttach(j, child, parent);
        dJointSetFixed(j);
        break;
    }
    joints.push_back(j);
  }

  // actuators: servos (module-local actuator index -> global servo index)
  std::vector<int> act_servo(def.actuators.size(), -1);
  for (size_t a = 0; a < def.actuators.size(); ++a) {
    const ActuatorDef& ad = def.actuators[a];
    if (ad.type != ActuatorType::Servo) {
      add_force_actuator(index, md, def, ad, frame, joints);
      act_servo[a] = static_cast<int>(servos.size()) - 1;
      continue;
    }
    const JointDef& jd = def.joints[ad.joint];
    Servo s;
    s.module = index;
    s.hinge = joints[ad.joint];
    s.model = ServoModel(ad.servo.value_or(cfg.servo));
    s.lo = std::isfinite(jd.lo) ? jd.lo : -kPi;
    s.hi = std::isfinite(jd.hi) ? jd.hi : kPi;
    s.motor = dJointCreateAMotor(world, nullptr);
    dJointAttach(s.motor, bodies[md.body0 + jd.child].id, bodies[md.body0 + jd.parent].id);
    dJointSetAMotorMode(s.motor, dAMotorUser);
    dJointSetAMotorNumAxes(s.motor, 1);
    const Eigen::Vector3d axis = frame.linear() * jd.axis.normalized();
    dJointSetAMotorAxis(s.motor, 0, 1, axis.x(), axis.y(), axis.z());
    dJointSetAMotorParam(s.motor, dParamFMax, kMotorFMax);
    act_servo[a] = static_cast<int>(servos.size());
    md.all.push_back(static_cast<int>(servos.size()));
    servos.push_back(std::move(s));
  }
  for (size_t a = 0; a < def.actuators.size(); ++a) {
    if (def.actuators[a].follows >= 0)
      servos[act_servo[a]].follows = act_servo[def.actuators[a].follows];
  }
  for (int a : driven_servo_actuators(def)) md.driven.push_back(act_servo[a]);

  for (const SensorDef& sd : def.sensors) {
    switch (sd.type) {
      case SensorType::MotorCurrent:
        md.adc_servo[sd.channel] = act_servo[sd.actuator];
        md.n_adc = std::max(md.n_adc, sd.channel + 1);
        break;
      case SensorType::Touch:
        md.touch.emplace_back(md.body0 + sd.body, sd.channel);
        break;
      case SensorType::Accelerometer:
      case SensorType::WheelEncoder:
        break;  // sensors.add_module
    }
  }
  std::vector<dBodyID> body_ids;
  for (int b = 0; b < md.nbody; ++b) body_ids.push_back(bodies[md.body0 + b].id);
  sensors.add_module(index, def, body_ids, joints, frame.linear());
  wheels.add_module(index, def.wheels, def.pads, body_ids, frame);

  md.front_body = md.body0 + def.front.body;
  md.back_body = md.body0 + def.back.body;
  md.front_in_body = to_iso(def.bodies[def.front.body].pose).inverse() * to_iso(def.front.frame);
  md.back_in_body = to_iso(def.bodies[def.back.body].pose).inverse() * to_iso(def.back.frame);
  modules.push_back(std::move(md));
}

// Linear servo and screw drive (force laws in module_library.h). Realised
// like the rotary servo: the part of the force that depends on the end-of-step
// rate v' is a one-axis linear motor row with dParamVel = v*, dParamCFM = 1/D,
// dParamFMax = fmax, i.e. F = clamp(D (v* - v'), -fmax, fmax), solved
// implicitly by ODE with the whole system:
//  * the back-EMF term fmax v'/v_free: D = fmax / v_free;
//  * the linear servo's proportional term inside its band (|u| < 1) is taken
//    at the end-of-step position pos + h v' (backward Euler):
//    fmax (ref - pos - h v')/l0 adds D = fmax h / l0 (stable for any stiffness;
//    its numerical damping, fmax h / l0, is what keeps the pure paper law
//    with v_free = 0 from ringing forever).
// With no v'-dependent part at all (saturated or a screw drive without
// v_free) the force is a plain external force. The linear motor is a separate
// joint (LMotor) rather than the slider's built-in motor, so that at a slider
// stop the law still holds (ODE replaces a powered joint's motor by its full
// fmax there).
void World::Impl::add_force_actuator(int index, Module& md, const ModuleDef& def,
                                     const ActuatorDef& ad, const Eigen::Isometry3d& frame,
                                     const std::vector<dJointID>& joints) {
  Servo s;
  s.module = index;
  s.fmax = ad.fmax_n;
  s.l0 = ad.l0_m;
  s.v_free = ad.v_free_m_s;
  s.stall_a = ad.stall_current_a > 0 ? ad.stall_current_a : cfg.servo.supply_v / cfg.servo.r;
  if (ad.type == ActuatorType::DcMotor) {
    // a one-axis angular motor on the hinge, as the rotary servo's
    const JointDef& jd = def.joints[ad.joint];
    s.kind = ServoKind::Screw;
    s.hinge = joints[ad.joint];
    s.lo = -1.0;
    s.hi = 1.0;
    s.motor = dJointCreateAMotor(world, nullptr);
    dJointAttach(s.motor, bodies[md.body0 + jd.child].id, bodies[md.body0 + jd.parent].id);
    dJointSetAMotorMode(s.motor, dAMotorUser);
    dJointSetAMotorNumAxes(s.motor, 1);
    const Eigen::Vector3d axis = frame.linear() * jd.axis.normalized();
    dJointSetAMotorAxis(s.motor, 0, 1, axis.x(), axis.y(), axis.z());
    dJointSetAMotorParam(s.motor, dParamFMax, 0.0);
    md.all.push_back(static_cast<int>(servos.size()));
    servos.push_back(std::move(s));
    return;
  }
  s.motor = dJointCreateLMotor(world, nullptr);
  dJointSetLMotorNumAxes(s.motor, 1);
  if (ad.type == ActuatorType::LinearServo) {
    const JointDef& jd = def.joints[ad.joint];
    s.kind = ServoKind::Linear;
    s.hinge = joints[ad.joint];
    s.lo = jd.lo;   // may be infinite
    s.hi = jd.hi;
    s.cmd = std::clamp(0.0, s.lo, s.hi);
    dJointAttach(s.motor, bodies[md.body0 + jd.child].id, bodies[md.body0 + jd.parent].id);
    const Eigen::Vector3d axis = frame.linear() * jd.axis.normalized();
    dJointSetLMotorAxis(s.motor, 0, 2, axis.x(), axis.y(), axis.z());  // fixed in the parent
  } else {
    s.kind = ServoKind::Screw;
    s.body = bodies[md.body0 + ad.body].id;
    s.lo = -1.0;
    s.hi = 1.0;
    s.dir = ad.direction.normalized();
    dVector3 axis;
    dBodyVectorToWorld(s.body, s.dir.x(), s.dir.y(), s.dir.z(), axis);
    dJointAttach(s.motor, s.body, nullptr);
    dJointSetLMotorAxis(s.motor, 0, 1, axis[0], axis[1], axis[2]);  // fixed in the body
  }
  dJointSetLMotorParam(s.motor, dParamFMax, 0.0);
  md.all.push_back(static_cast<int>(servos.size()));
  servos.push_back(std::move(s));
}

// rate along the actuator's axis as its motor row measures it: the slider rate
// (relative velocity of the two bodies along the axis), or the screw-driven
// body's velocity along its drive axis; m/s
double World::Impl::actuator_rate(const Servo& s) const {
  if (s.kind == ServoKind::Linear) return dJointGetSliderPositionRate(s.hinge);
  if (s.hinge) return dJointGetHingeAngleRate(s.hinge);  // DC motor: rad/s
  dVector3 ax;  // (dJointGetLMotorAxis would give the body-frame axis)
  dBodyVectorToWorld(s.body, s.dir.x(), s.dir.y(), s.dir.z(), ax);
  const dReal* v = dBodyGetLinearVel(s.body);
  return ax[0] * v[0] + ax[1] * v[1] + ax[2] * v[2];
}

void World::Impl::begin_force_actuator(Servo& s) {
  s.on = modules[s.module].powered && s.enabled;
  s.law_damping = s.law_rate = s.law_force = 0.0;
  if (s.on) {
    double d = s.v_free > 0 ? s.fmax / s.v_free : 0.0;  // back-EMF
    double f0;                                          // the part known now
    if (s.kind == ServoKind::Linear) {
      const double u = (s.cmd - dJointGetSliderPosition(s.hinge)) / s.l0;
      if (std::fabs(u) < 1.0) {
        f0 = s.fmax * u;
        d += s.fmax * h / s.l0;
      } else {
        f0 = u > 0 ? s.fmax : -s.fmax;
      }
    } else {
      f0 = s.fmax * s.cmd;
    }
    if (d > 0) {
      s.law_damping = d;
      s.law_rate = f0 / d;
    } else {
      s.law_force = f0;
    }
  }
  if (s.hinge && s.kind == ServoKind::Screw) {  // DC motor: always has a speed term
    dJointSetAMotorParam(s.motor, dParamVel, s.law_rate);
    dJointSetAMotorParam(s.motor, dParamCFM, s.law_damping > 0 ? 1.0 / s.law_damping : 1.0);
    dJointSetAMotorParam(s.motor, dParamFMax, s.law_damping > 0 ? s.fmax : 0.0);
    return;
  }
  if (s.law_damping > 0) {
    dJointSetLMotorParam(s.motor, dParamVel, s.law_rate);
    dJointSetLMotorParam(s.motor, dParamCFM, 1.0 / s.law_damping);
    dJointSetLMotorParam(s.motor, dParamFMax, s.fmax);
    return;
  }
  dJointSetLMotorParam(s.motor, dParamFMax, 0.0);
  if (s.law_force == 0.0) return;
  if (s.kind == ServoKind::Linear) {
    dJointAddSliderForce(s.hinge, s.law_force);
  } else {
    dVector3 ax;
    dBodyVectorToWorld(s.body, s.dir.x(), s.dir.y(), s.dir.z(), ax);
    dBodyAddForce(s.body, s.law_force * ax[0], s.law_force * ax[1], s.law_force * ax[2]);
  }
}

void World::Impl::end_force_actuator(Servo& s) {
  s.force = s.law_damping > 0
                ? std::clamp(s.law_damping * (s.law_rate - actuator_rate(s)), -s.fmax, s.fmax)
                : s.law_force;
  s.i_motor = s.on ? s.force / s.fmax * s.stall_a : 0.0;
  // RC filter of |i|, exact for |i| held over the step (as ServoModel)
  const double a = std::fabs(s.i_motor);
  s.i_f = a + (s.i_f - a) * filter_e;
}

uint16_t World::Impl::adc_counts(const Servo& s) const {
  if (s.kind == ServoKind::Rotary) return s.model.adc_counts();
  const double fs = cfg.servo.adc_full_scale_a;
  if (!(fs > 0.0)) return 0;
  const double c = std::floor(s.i_f / fs * 1023.0 + 0.5);
  return static_cast<uint16_t>(std::clamp(c, 0.0, 1023.0));
}

void World::Impl::build() {
  if (cfg.dt_us <= 0) throw std::invalid_argument("dt_us must be > 0");
  h = static_cast<double>(cfg.dt_us) * 1e-6;
  filter_e = cfg.servo.current_filter_tau_s > 0 ? std::exp(-h / cfg.servo.current_filter_tau_s) : 0.0;
  ode_init_once();
  world = dWorldCreate();
  dWorldSetGravity(world, 0, 0, -cfg.gravity_m_s2);
  dWorldSetERP(world, 0.2);
  dWorldSetCFM(world, 1e-9);
  dWorldSetQuickStepNumIterations(world, std::max(1, cfg.solver_iterations));
  dWorldSetAutoDisableFlag(world, 0);
  dWorldSetContactSurfaceLayer(world, kSurfaceLayer);
  space = dSimpleSpaceCreate(nullptr);
  env = std::make_unique<EnvironmentGeoms>(cfg.environment, space);
  for (const std::string& surface : env->surfaces())
    env_materials.push_back(
        contact_material(cfg.environment, surface, module_surface_name(), cfg.ground));
  cfg.module_contact = contact_material(cfg.environment, module_surface_name(),
                                        module_surface_name(), cfg.module_contact);
  contact_group = dJointGroupCreate(0);
  wall_probe = std::make_unique<WallProbe>(env->pipe_layout(), env->geoms());
  wheels.init(world, wall_probe.get(), h, kSurfaceLayer);
  rand_seed = static_cast<unsigned long>(cfg.seed);
  sensors.init(world, cfg.seed, cfg.gravity_m_s2);

  std::vector<ModuleDef> defs;
  defs.reserve(cfg.chain.size());
  for (const std::string& name : cfg.chain) {
    const auto custom = std::find_if(cfg.module_types.begin(), cfg.module_types.end(),
                                     [&](const ModuleDef& d) { return d.type == name; });
    defs.push_back(custom != cfg.module_types.end() ? *custom : builtin_module_def(name));
    validate_module_def(defs.back());
  }
  // head's front face at head_position, chain along +x rotated by heading
  // about z, or as head_orientation says
  Eigen::Isometry3d face = Eigen::Isometry3d::Identity();
  face.linear() = cfg.head_orientation
                      ? cfg.head_orientation->normalized().toRotationMatrix()
                      : Eigen::AngleAxisd(cfg.heading_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  face.translation() = cfg.head_position;
  for (size_t k = 0; k < defs.size(); ++k) {
    const Eigen::Isometry3d frame = face * to_iso(defs[k].front.frame).inverse();
    add_module(static_cast<int>(k), defs[k], frame);
    face = frame * to_iso(defs[k].back.frame);
  }
  for (size_t k = 0; k + 1 < modules.size(); ++k) {
    dJointID j = dJointCreateFixed(world, nullptr);
    dJointAttach(j, bodies[modules[k].back_body].id, bodies[modules[k + 1].front_body].id);
    dJointSetFixed(j);
  }

  // memory for step(): ODE's stepper keeps what it reserved; the contact
  // group keeps its arenas when emptied, so fill it once and empty it
  dWorldStepReserveInfo reserve{};
  reserve.struct_size = sizeof(reserve);
  reserve.reserve_factor = 1.2f;
  reserve.reserve_minimum = kStepReserveBytes;
  dWorldSetStepMemoryReservationPolicy(world, &reserve);
  dContact dummy{};
  size_t n_wheels = 0;
  for (size_t m = 0; m < modules.size(); ++m) n_wheels += wheels.count(static_cast<int>(m));
  const size_t warm = 64 + kWarmContactsPerGeom * bodies.size() + n_wheels;
  if (cfg.log_contact_forces)
    force_log.init(static_cast<int>(bodies.size()), static_cast<int>(warm));
  for (size_t k = 0; k < warm; ++k) dJointCreateContact(world, contact_group, &dummy);
  dJointGroupEmpty(contact_group);
}

World::World(const WorldConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->cfg = config;
  try {
    impl_->build();
  } catch (...) {
    if (impl_->contact_group) dJointGroupDestroy(impl_->contact_group);
    if (impl_->space) dSpaceDestroy(impl_->space);
    if (impl_->world) dWorldDestroy(impl_->world);
    throw;
  }
}

World::~World() {
  dJointGroupDestroy(impl_->contact_group);
  dSpaceDestroy(impl_->space);   // destroys its geoms (cleanup mode)
  dWorldDestroy(impl_->world);   // destroys bodies and joints
}

int World::module_count() const { return static_cast<int>(impl_->modules.size()); }
const std::string& World::module_type(int module) const { return impl_->mod(module).type; }
int World::servo_count(int module) const {
  return static_cast<int>(impl_->mod(module).driven.size());
}

void World::set_servo_setpoint(int module, int servo, double rad) {
  Impl::Servo& s = impl_->servos[impl_->servo_index(module, servo)];
  if (std::isnan(rad)) return;
  if (s.kind == ServoKind::Rotary)
    s.model.set_setpoint(std::clamp(rad, s.lo, s.hi));
  else
    s.cmd = std::clamp(rad, s.lo, s.hi);
}

World::ServoKind World::servo_kind(int module, int servo) const {
  return impl_->servos[impl_->servo_index(module, servo)].kind;
}

double World::servo_from_wire(ServoKind kind, int32_t wire) {
  switch (kind) {
    case ServoKind::Rotary: return wire * 1e-3 * kPi / 180.0;  // millidegrees
    case ServoKind::Linear: return wire * 1e-6;                // micrometres
    case ServoKind::Screw: return wire * 1e-3;                 // per mille
  }
  return 0.0;
}

int32_t World::servo_to_wire(ServoKind kind, double value) {
  double w = 0;
  switch (kind) {
    case ServoKind::Rotary: w = value * 180.0 / kPi * 1e3; break;
    case ServoKind::Linear: w = value * 1e6; break;
    case ServoKind::Screw: w = value * 1e3; break;
  }
  if (!std::isfinite(w)) return 0;
  return static_cast<int32_t>(std::lround(std::clamp(w, -2147483647.0, 2147483647.0)));
}

void World::set_servo_enabled(int module, int servo, bool enabled) {
  impl_->servos[impl_->servo_index(module, servo)].enabled = enabled;
}

void World::set_module_powered(int module, bool powered) {
  impl_->mod(module);
  impl_->modules[module].powered = powered;
}

void World::step() {
  Impl& w = *impl_;
  dAllocateODEDataForThread(dAllocateMaskAll);  // no-op once done for this thread
  // servo torque laws for this step (followers copy their master's set-point)
  for (Impl::Servo& s : w.servos) {
    if (s.kind != ServoKind::Rotary) {
      w.begin_force_actuator(s);
      continue;
    }
    if (s.follows >= 0) s.model.set_setpoint(w.servos[s.follows].model.setpoint());
    const Impl::Module& md = w.modules[s.module];
    const bool master_enabled = s.follows >= 0 ? w.servos[s.follows].enabled : s.enabled;
    s.model.set_enabled(md.powered && master_enabled);
    const ServoModel::StepLaw law = s.model.begin_step(dJointGetHingeAngle(s.hinge),
                                                       dJointGetHingeAngleRate(s.hinge), w.h);
    dJointSetAMotorParam(s.motor, dParamVel, law.target_rate);
    dJointSetAMotorParam(s.motor, dParamCFM, 1.0 / law.damping);
  }
  for (Impl::Body& b : w.bodies) b.touched = false;
  w.contact_count = 0;
  dRandSetSeed(w.rand_seed);
  w.force_log.begin_step();
  dSpaceCollide(w.space, &w, &Impl::near_callback);
  w.contact_count += w.wheels.begin_step(w.contact_group);
  dWorldQuickStep(w.world, w.h);
  w.rand_seed = dRandGetSeed();
  w.wheels.end_step();
  if (w.force_log.enabled()) w.force_log.end_step();
  dJointGroupEmpty(w.contact_group);
  for (Impl::Servo& s : w.servos) {
    if (s.kind == ServoKind::Rotary)
      s.model.end_step(dJointGetHingeAngleRate(s.hinge));
    else
      w.end_force_actuator(s);
  }
  w.sensors.step_end(w.h);
  w.time_us += w.cfg.dt_us;
}

int64_t World::time_us() const { return impl_->time_us; }
int64_t World::dt_us() const { return impl_->cfg.dt_us; }

void World::sample(int module, ModuleSample* out) const {
  const Impl::Module& md = impl_->mod(module);
  *out = ModuleSample{};
  out->n_servos = static_cast<int>(md.driven.size());
  out->n_adc = md.n_adc;
  out->n_counters = 0;
  impl_->sensors.sample(module, md.powered, impl_->time_us, out);  // accelerometers, encoders
  if (!md.powered) return;
  for (int s = 0; s < out->n_servos; ++s) {
    const Impl::Servo& sv = impl_->servos[md.driven[s]];
    switch (sv.kind) {
      case ServoKind::Rotary: out->servo_angle_rad[s] = dJointGetHingeAngle(sv.hinge); break;
      case ServoKind::Linear: out->servo_angle_rad[s] = dJointGetSliderPosition(sv.hinge); break;
      case ServoKind::Screw: out->servo_angle_rad[s] = sv.cmd; break;
    }
  }
  for (int c = 0; c < md.n_adc; ++c)
    if (md.adc_servo[c] >= 0) out->adc[c] = impl_->adc_counts(impl_->servos[md.adc_servo[c]]);
  for (const auto& [body, bit] : md.touch)
    if (impl_->bodies[body].touched) out->digital_in |= static_cast<uint16_t>(1u << bit);
}

double World::module_supply_current_a(int module) const {
  const Impl::Module& md = impl_->mod(module);
  if (!md.powered) return 0.0;
  double sum = 0;
  // a servo without drive free-wheels: its decaying current is not drawn from the supply
  for (int s : md.all) {
    const Impl::Servo& sv = impl_->servos[s];
    if (sv.kind == ServoKind::Rotary) {
      if (sv.model.enabled()) sum += std::fabs(sv.model.current_a());
    } else if (sv.on) {  // linear servo, screw drive: the motor current (module_library.h)
      sum += std::fabs(sv.i_motor);
    }
  }
  return sum;
}

Eigen::Vector3d World::chain_com() const {
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  double mass = 0;
  for (const Impl::Body& b : impl_->bodies) {
    dMass m;
    dBodyGetMass(b.id, &m);
    const dReal* p = dBodyGetPosition(b.id);
    acc += m.mass * Eigen::Vector3d(p[0], p[1], p[2]);
    mass += m.mass;
  }
  return mass > 0 ? Eigen::Vector3d(acc / mass) : Eigen::Vector3d::Zero();
}

int World::body_count(int module) const { return impl_->mod(module).nbody; }

const std::string& World::body_name(int module, int body) const {
  return impl_->bodies[impl_->body_index(module, body)].name;
}

World::BodyState World::body_state(int module, int body) const {
  dBodyID id = impl_->bodies[impl_->body_index(module, body)].id;
  BodyState s;
  dMass m;
  dBodyGetMass(id, &m);
  s.mass_kg = m.mass;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s.inertia_kg_m2(r, c) = m.I[r * 4 + c];
  const dReal* p = dBodyGetPosition(id);
  const dReal* q = dBodyGetQuaternion(id);
  const dReal* v = dBodyGetLinearVel(id);
  s.position = Eigen::Vector3d(p[0], p[1], p[2]);
  s.quaternion_wxyz = Eigen::Vector4d(q[0], q[1], q[2], q[3]);
  s.linear_velocity = Eigen::Vector3d(v[0], v[1], v[2]);
  return s;
}

double World::servo_angle_rad(int module, int servo) const {
  const Impl::Servo& s = impl_->servos[impl_->servo_index(module, servo)];
  switch (s.kind) {
    case ServoKind::Rotary: return dJointGetHingeAngle(s.hinge);
    case ServoKind::Linear: return dJointGetSliderPosition(s.hinge);
    case ServoKind::Screw: return impl_->actuator_rate(s);
  }
  return 0.0;
}
double World::servo_setpoint_rad(int module, int servo) const {
  const Impl::Servo& s = impl_->servos[impl_->servo_index(module, servo)];
  return s.kind == ServoKind::Rotary ? s.model.setpoint() : s.cmd;
}
double World::servo_current_a(int module, int servo) const {
  const Impl::Servo& s = impl_->servos[impl_->servo_index(module, servo)];
  return s.kind == ServoKind::Rotary ? s.model.current_a() : s.i_motor;
}
double World::servo_filtered_current_a(int module, int servo) const {
  const Impl::Servo& s = impl_->servos[impl_->servo_index(module, servo)];
  return s.kind == ServoKind::Rotary ? s.model.filtered_current_a() : s.i_f;
}
double World::servo_effort(int module, int servo) const {
  const Impl::Servo& s = impl_->servos[impl_->servo_index(module, servo)];
  return s.kind == ServoKind::Rotary ? s.model.motor_torque_nm() : s.force;
}

void World::pin_body(int module, int body) {
  dJointID j = dJointCreateFixed(impl_->world, nullptr);
  dJointAttach(j, impl_->bodies[impl_->body_index(module, body)].id, nullptr);
  dJointSetFixed(j);
}

void World::add_body_torque(int module, int body, const Eigen::Vector3d& torque_nm) {
  dBodyAddTorque(impl_->bodies[impl_->body_index(module, body)].id, torque_nm.x(), torque_nm.y(),
                 torque_nm.z());
}

void World::add_body_force(int module, int body, const Eigen::Vector3d& force_n) {
  dBodyAddForce(impl_->bodies[impl_->body_index(module, body)].id, force_n.x(), force_n.y(),
                force_n.z());
}

double World::max_docking_error_m() const {
  double worst = 0;
  const auto& mods = impl_->modules;
  for (size_t k = 0; k + 1 < mods.size(); ++k) {
    const Eigen::Vector3d a =
        (body_iso(impl_->bodies[mods[k].back_body].id) * mods[k].back_in_body).translation();
    const Eigen::Vector3d b =
        (body_iso(impl_->bodies[mods[k + 1].front_body].id) * mods[k + 1].front_in_body)
            .translation();
    worst = std::max(worst, (a - b).norm());
  }
  return worst;
}

int World::last_contact_count() const { return impl_->contact_count; }

int World::wheel_count(int module) const { return impl_->wheels.count(module); }
const std::string& World::wheel_name(int module, int wheel) const {
  return impl_->wheels.name(module, wheel);
}
World::ContactForce World::body_contact_force(int module, int body) const {
  if (!impl_->force_log.enabled())
    throw std::logic_error("body_contact_force needs WorldConfig::log_contact_forces");
  const ContactForceLog::Sum& s = impl_->force_log.body(impl_->body_index(module, body));
  return ContactForce{s.normal_n, s.force, s.contacts};
}

World::WheelState World::wheel_state(int module, int wheel) const {
  const WheelContacts::State& s = impl_->wheels.state(module, wheel);
  WheelState out;
  out.on = s.on;
  out.reach_m = s.reach_m;
  out.normal_n = s.normal_n;
  out.across_n = s.across_n;
  out.point = s.point;
  return out;
}

std::string World::trace_header() const {
  std::string out = "t_s";
  static const char* kBodyCols[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  for (size_t m = 0; m < impl_->modules.size(); ++m) {
    const Impl::Module& md = impl_->modules[m];
    const std::string pre = "m" + std::to_string(m) + ".";
    for (int b = 0; b < md.nbody; ++b)
      for (const char* c : kBodyCols) out += "," + pre + impl_->bodies[md.body0 + b].name + "." + c;
    for (size_t s = 0; s < md.driven.size(); ++s) {
      const std::string sp = pre + "s" + std::to_string(s) + ".";
      const Impl::Servo& sv = impl_->servos[md.driven[s]];
      switch (sv.kind) {
        case ServoKind::Rotary: out += "," + sp + "setpoint_deg," + sp + "angle_deg"; break;
        case ServoKind::Linear: out += "," + sp + "setpoint_mm," + sp + "position_mm"; break;
        case ServoKind::Screw:
          out += "," + sp + "command," + sp + (sv.hinge ? "speed_rad_s" : "speed_mm_s");
          break;
      }
      out += "," + sp + "current_a";
    }
    out += "," + pre + "supply_a";
    impl_->wheels.append_header(static_cast<int>(m), pre, &out);
  }
  out += "\n";
  return out;
}

void World::append_trace_row(std::string* out) const {
  constexpr double kDeg = 180.0 / kPi;
  char buf[160];
  const int64_t t = impl_->time_us;
  std::snprintf(buf, sizeof buf, "%" PRId64 ".%06" PRId64, t / 1000000, t % 1000000);
  *out += buf;
  for (size_t m = 0; m < impl_->modules.size(); ++m) {
    const Impl::Module& md = impl_->modules[m];
    for (int b = 0; b < md.nbody; ++b) {
      dBodyID id = impl_->bodies[md.body0 + b].id;
      const dReal* p = dBodyGetPosition(id);
      const dReal* q = dBodyGetQuaternion(id);
      std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f", p[0], p[1], p[2], q[0],
                    q[1], q[2], q[3]);
      *out += buf;
    }
    for (int s : md.driven) {
      const Impl::Servo& sv = impl_->servos[s];
      switch (sv.kind) {
        case ServoKind::Rotary:
          std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.5f", sv.model.setpoint() * kDeg,
                        dJointGetHingeAngle(sv.hinge) * kDeg, sv.model.current_a());
          break;
        case ServoKind::Linear:
          std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.5f", sv.cmd * 1e3,
                        dJointGetSliderPosition(sv.hinge) * 1e3, sv.i_motor);
          break;
        case ServoKind::Screw:  // screw drive: mm/s; DC motor: rad/s
          std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.5f", sv.cmd,
                        impl_->actuator_rate(sv) * (sv.hinge ? 1.0 : 1e3), sv.i_motor);
          break;
      }
      *out += buf;
    }
    std::snprintf(buf, sizeof buf, ",%.5f", module_supply_current_a(static_cast<int>(m)));
    *out += buf;
    impl_->wheels.append_row(static_cast<int>(m), out);
  }
  *out += "\n";
}

}  // namespace chainsim
