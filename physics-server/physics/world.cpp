// The ODE world of one run: assembly and the step. See world.h (interface),
// model/module_def.h (how a module type is described), chain_model.h (the
// chain's definitions and frames), module_builder.h (its
// bodies and joints), actuators/ (servo, linear servo, screw drive, DC
// motor), contact.h (collisions), wheels/ (wheels and pads on the wall) and
// sensors/.
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
// Solver: QuickStep, WorldConfig::solver_iterations (default 30), cost about
// linear in the iterations. Its iteration does not converge: a servo holding
// a module against gravity jitters (under one potentiometer count, 0.18
// degrees, at 30), and a gripping support creeps back under an extension's
// push. WorldConfig::Solver::Exact steps with dWorldStep (the exact LCP)
// instead, at several times the cost. The figures: docs/benchmarks.md
// ("Physics step cost") and docs/firmware.md ("Inchworm").
// Global ERP/CFM 0.2 / 1e-9 (stiff joints; a
// softer CFM up to 1e-5 changed nothing measurable); contacts use their
// Material's soft ERP/CFM.
#include "physics/world.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <mutex>
#include <stdexcept>

#include "environment/environment_geoms.h"
#include "environment/pipe_wall_probe.h"
#include "physics/contact.h"
#include "physics/module_builder.h"
#include "physics/sensors/module_channels.h"
#include "physics/sensors/sensors.h"
#include "physics/wheels/wheel_contacts.h"

namespace chainsim {

namespace {

constexpr unsigned kStepReserveBytes = 4u << 20;  // ODE stepper working memory, reserved
constexpr int kWarmContactsPerGeom = 8;           // contact joints pre-allocated per geom
constexpr double kSurfaceLayer = 1e-4;            // m, ODE's allowed contact penetration

// ODE's messages (non-fatal) go to stderr as ODE's own handler prints them,
// but for the exact solver's "LCP internal error" (d_ERR_LCP, a degenerate
// pivot in dLCP: the step goes on with the solution found so far) within
// World::step, which the stepping thread counts for
// World::degenerate_lcp_steps (other dWorldStep users, e.g. the servo stand,
// still see them printed)
thread_local bool t_counting_lcp = false;
thread_local int64_t t_lcp_messages = 0;

void ode_message(int num, const char* msg, va_list ap) {
  if (num == d_ERR_LCP && t_counting_lcp) {
    ++t_lcp_messages;
    return;
  }
  std::fprintf(stderr, "ODE Message %d: ", num);
  std::vfprintf(stderr, msg, ap);
  std::fprintf(stderr, "\n");
}

void ode_init_once() {
  static std::once_flag flag;
  std::call_once(flag, [] {
    dInitODE2(0);
    dSetMessageHandler(ode_message);
  });
  dAllocateODEDataForThread(dAllocateMaskAll);
}

// the environment's surfaces and the modules: each pair's material, from the
// environment's pair table or the config's defaults
ContactMaterials resolve_materials(const WorldConfig& cfg, const EnvironmentGeoms& env) {
  ContactMaterials m;
  for (const std::string& surface : env.surfaces())
    m.surface.push_back(contact_material(cfg.environment, surface, module_surface_name(), cfg.ground));
  m.ground = cfg.ground;
  m.module_module = contact_material(cfg.environment, module_surface_name(), module_surface_name(),
                                     cfg.module_contact);
  return m;
}

}  // namespace

struct World::Impl {
  // a module's part: its ODE body is shared with the parts rigidly joined to it
  struct Body {
    dBodyID id = nullptr;
    std::string name;
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  // the part's frame in id's frame
    dMass mass{};                                              // the part's own, in its frame
    dGeomID geom = nullptr;                                    // its collision shape (nullptr: none)
    Eigen::Isometry3d pose() const { return body_isometry(id) * offset; }  // part frame -> world
  };
  struct Module {
    std::string type;
    int body0 = 0, nbody = 0;
    std::vector<int> driven;   // actuator indices firmware drives (servo s = driven[s])
    std::vector<int> all;      // all actuator indices of the module
    bool powered = true;
    ModuleChannels channels;   // servo position, motor current and touch sensors
    int front_body = 0, back_body = 0;              // body indices
    Eigen::Isometry3d front_in_body, back_in_body;  // face frames in their bodies' frames
  };

  explicit Impl(int64_t dt) : dt_us(dt), h(static_cast<double>(dt) * 1e-6) {}
  ~Impl();
  void build(const WorldConfig& cfg, const ChainModel& chain);
  void add_module(int index, const ModuleDef& def, const Eigen::Isometry3d& frame,
                  const ModuleBodies& parts, const WorldConfig& cfg);
  void check_start_clear() const;
  void add_docks(const WorldConfig::DockConfig& dc);
  void begin_actuators();
  void end_actuators();

  const Module& mod(int m) const;
  int actuator_index(int m, int s) const;
  const Actuator& servo(int m, int s) const { return actuators[actuator_index(m, s)]; }
  int body_index(int m, int b) const;

  const int64_t dt_us;
  const double h;            // dt_us in seconds
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  std::unique_ptr<EnvironmentGeoms> env;   // destroyed after the space (its triangle data)
  std::unique_ptr<Contacts> contacts;
  std::unique_ptr<WallProbe> wall_probe;   // where wheel arms and pads meet the wall
  std::unique_ptr<WheelContacts> wheels;   // wheel sets and pads (wheels/wheel_contacts.h)
  unsigned long rand_seed = 0;             // ODE's random state between steps
  bool exact = false;                      // dWorldStep instead of dWorldQuickStep (WorldConfig::solver)
  int64_t degenerate_lcp_steps = 0;        // exact: steps whose LCP met a degenerate pivot
  int64_t time_us = 0;

  std::vector<Body> bodies;
  std::vector<Actuator> actuators;
  std::vector<Module> modules;
  Sensors sensors;   // accelerometers, wheel encoders, joint friction (sensors.h)
  // docks as joints (WorldConfig::dock): dock k joins module k's back part
  // (body1) to module k + 1's front part (body2); sized once, so the
  // feedback ODE writes into stays where it is
  struct Dock {
    dJointID ball = nullptr, motor = nullptr;
    dJointFeedback ball_fb{}, motor_fb{};
  };
  std::vector<Dock> docks;
};

World::Impl::~Impl() {
  contacts.reset();                // its joint group
  wheels.reset();                  // its joint group
  if (space) dSpaceDestroy(space);  // destroys its geoms (cleanup mode)
  if (world) dWorldDestroy(world);  // destroys bodies and joints
}

void World::Impl::build(const WorldConfig& cfg, const ChainModel& chain) {
  const std::vector<ModuleDef>& defs = chain.modules;
  const std::vector<Eigen::Isometry3d>& frames = chain.frames;
  ode_init_once();
  world = dWorldCreate();
  dWorldSetGravity(world, 0, 0, -cfg.gravity_m_s2);
  dWorldSetERP(world, 0.2);
  dWorldSetCFM(world, 1e-9);
  dWorldSetQuickStepNumIterations(world, std::max(1, cfg.solver_iterations));
  exact = cfg.solver == WorldConfig::Solver::Exact;
  dWorldSetAutoDisableFlag(world, 0);
  dWorldSetContactSurfaceLayer(world, kSurfaceLayer);
  space = dSimpleSpaceCreate(nullptr);
  env = std::make_unique<EnvironmentGeoms>(cfg.environment, space);
  contacts = std::make_unique<Contacts>(world, resolve_materials(cfg, *env));
  wall_probe = std::make_unique<WallProbe>(env->pipe_layout(), env->geoms());
  wheels = std::make_unique<WheelContacts>(world, wall_probe.get(), h, kSurfaceLayer);
  rand_seed = static_cast<unsigned long>(cfg.seed);
  sensors.init(world, cfg.seed, cfg.gravity_m_s2);

  // docked faces share one body (module_builder.h), or are joined by joints
  const std::vector<ModuleBodies> parts = build_chain_bodies(world, space, defs, frames, !cfg.dock);
  for (size_t k = 0; k < defs.size(); ++k)
    add_module(static_cast<int>(k), defs[k], frames[k], parts[k], cfg);
  if (cfg.dock) add_docks(*cfg.dock);
  check_start_clear();

  // memory for step(): ODE's stepper keeps what it reserved; the contact
  // group keeps its arenas when emptied, so fill it once and empty it
  dWorldStepReserveInfo reserve{};
  reserve.struct_size = sizeof(reserve);
  reserve.reserve_factor = 1.2f;
  reserve.reserve_minimum = kStepReserveBytes;
  dWorldSetStepMemoryReservationPolicy(world, &reserve);
  contacts->warm_up(64 + kWarmContactsPerGeom * bodies.size());
  wheels->warm_up();
}

void World::Impl::add_module(int index, const ModuleDef& def, const Eigen::Isometry3d& frame,
                             const ModuleBodies& parts, const WorldConfig& cfg) {
  Module md;
  md.type = def.type;
  md.body0 = static_cast<int>(bodies.size());
  md.nbody = static_cast<int>(def.bodies.size());
  for (int b = 0; b < md.nbody; ++b) {
    contacts->add_body(parts.geoms[b], index);
    bodies.push_back({parts.bodies[b], def.bodies[b].name, parts.offsets[b], part_mass(def.bodies[b]),
                      parts.geoms[b]});
  }

  // actuators, in definition order (module-local index -> the World's)
  std::vector<int> act(def.actuators.size(), -1);
  for (size_t a = 0; a < def.actuators.size(); ++a) {
    act[a] = static_cast<int>(actuators.size());
    md.all.push_back(act[a]);
    actuators.push_back(
        make_actuator(index, def, static_cast<int>(a), world, parts, frame, cfg.servo, h));
  }
  for (size_t a = 0; a < def.actuators.size(); ++a)
    if (def.actuators[a].follows >= 0) actuators[act[a]].follows = act[def.actuators[a].follows];
  for (int a : driven_servo_actuators(def)) md.driven.push_back(act[a]);

  for (const SensorDef& sd : def.sensors) {
    switch (sd.type) {
      case SensorType::MotorCurrent:
        md.channels.adc_actuator[sd.channel] = act[sd.actuator];
        md.channels.n_adc = std::max(md.channels.n_adc, sd.channel + 1);
        break;
      case SensorType::Touch: {
        ModuleChannels::Touch tw;
        tw.body = md.body0 + sd.body;
        tw.bit = sd.channel;
        tw.sectors = sd.sectors;
        tw.first_rad = sd.first_deg * M_PI / 180;
        tw.half_width_rad = sd.half_width_deg * M_PI / 180;
        tw.module_from_body = to_isometry(def.bodies[sd.body].pose) * parts.offsets[sd.body].inverse();
        if (sd.sectors > 1) contacts->keep_push(tw.body);
        md.channels.touch.push_back(tw);
        break;
      }
      case SensorType::Accelerometer:
      case SensorType::WheelEncoder:
        break;  // sensors.add_module
    }
  }
  sensors.add_module(index, def, parts, frame.linear());
  wheels->add_module(index, def.wheels, def.pads, parts.bodies, frame);

  md.front_body = md.body0 + def.front.body;
  md.back_body = md.body0 + def.back.body;
  md.front_in_body = parts.offsets[def.front.body] *
                     to_isometry(def.bodies[def.front.body].pose).inverse() * to_isometry(def.front.frame);
  md.back_in_body = parts.offsets[def.back.body] *
                    to_isometry(def.bodies[def.back.body].pose).inverse() * to_isometry(def.back.frame);
  modules.push_back(std::move(md));
}

// each dock as a ball joint at the faces' centre (its three rows at the
// world's ERP/CFM, as stiff as the solver makes a joint) and an angular
// motor in Euler mode (axis 0 the back face's x on body1, axis 2 the front
// face's z on body2) whose stops at +-play on all three angles hold the
// faces' relative turn, with the dock's stiffness and damping as the stops'
// ERP and CFM. With no play the stops are two-sided at 0 (ODE treats equal
// stops as a fixed position).
void World::Impl::add_docks(const WorldConfig::DockConfig& dc) {
  docks.resize(modules.size() > 0 ? modules.size() - 1 : 0);
  for (size_t k = 0; k + 1 < modules.size(); ++k) {
    const Body& a = bodies[modules[k].back_body];
    const Body& b = bodies[modules[k + 1].front_body];
    const Eigen::Isometry3d fa = body_isometry(a.id) * modules[k].back_in_body;
    const Eigen::Isometry3d fb = body_isometry(b.id) * modules[k + 1].front_in_body;
    Dock& d = docks[k];
    d.ball = dJointCreateBall(world, nullptr);
    dJointAttach(d.ball, a.id, b.id);
    dJointSetBallAnchor(d.ball, fa.translation().x(), fa.translation().y(), fa.translation().z());
    dJointSetFeedback(d.ball, &d.ball_fb);
    d.motor = dJointCreateAMotor(world, nullptr);
    dJointAttach(d.motor, a.id, b.id);
    dJointSetAMotorMode(d.motor, dAMotorEuler);
    const Eigen::Vector3d x = fa.linear().col(0), z = fb.linear().col(2);
    dJointSetAMotorAxis(d.motor, 0, 1, x.x(), x.y(), x.z());
    dJointSetAMotorAxis(d.motor, 2, 2, z.x(), z.y(), z.z());
    static const int kLo[3] = {dParamLoStop, dParamLoStop2, dParamLoStop3};
    static const int kHi[3] = {dParamHiStop, dParamHiStop2, dParamHiStop3};
    static const int kErp[3] = {dParamStopERP, dParamStopERP2, dParamStopERP3};
    static const int kCfm[3] = {dParamStopCFM, dParamStopCFM2, dParamStopCFM3};
    const double play_rad = dc.play_deg * M_PI / 180;
    for (int i = 0; i < 3; ++i) {
      dJointSetAMotorParam(d.motor, kLo[i], -play_rad);
      dJointSetAMotorParam(d.motor, kHi[i], play_rad);
      if (dc.stiffness_nm_per_rad > 0) {
        const double hk = h * dc.stiffness_nm_per_rad, c = dc.damping_nm_s_per_rad;
        dJointSetAMotorParam(d.motor, kErp[i], hk / (hk + c));
        dJointSetAMotorParam(d.motor, kCfm[i], 1.0 / (hk + c));
      }
    }
    dJointSetFeedback(d.motor, &d.motor_fb);
  }
}

// a body that starts inside the environment is thrown out of it at the
// first step, at a speed the divergence check then reports: refuse such a
// start instead, naming the deepest body (contacts settle within ODE's
// surface layer, 0.1 mm; 1 mm is far beyond any placement that rests)
void World::Impl::check_start_clear() const {
  constexpr double kMaxStartDepth = 1e-3;  // m
  dContactGeom c[Contacts::kMaxContactsPerPair];
  double worst = kMaxStartDepth;
  int worst_body = -1;
  for (size_t b = 0; b < bodies.size(); ++b) {
    if (!bodies[b].geom) continue;
    for (dGeomID e : env->geoms()) {
      const int n = dCollide(bodies[b].geom, e, Contacts::kMaxContactsPerPair, c, sizeof(dContactGeom));
      for (int i = 0; i < n; ++i)
        if (c[i].depth > worst) {
          worst = c[i].depth;
          worst_body = static_cast<int>(b);
        }
    }
  }
  if (worst_body < 0) return;
  for (size_t m = 0; m < modules.size(); ++m) {
    const Module& md = modules[m];
    if (worst_body < md.body0 || worst_body >= md.body0 + md.nbody) continue;
    char depth[32];
    std::snprintf(depth, sizeof depth, "%.1f", worst * 1e3);
    throw WorldSetupError("module " + std::to_string(m) + " (" + md.type + ") body '" + bodies[worst_body].name +
                          "' starts " + depth + " mm inside the environment: place the chain clear of it");
  }
}

void World::Impl::begin_actuators() {
  for (Actuator& a : actuators) {
    // a passive servo copies its master's set-point and enable
    const Actuator& master = a.follows >= 0 ? actuators[a.follows] : a;
    if (a.follows >= 0)
      std::get<RotaryServo>(a.device).copy_setpoint(std::get<RotaryServo>(master.device));
    const bool driven = modules[a.module].powered && master.enabled;
    a.visit([&](auto& d) { d.begin_step(driven, h); });
  }
}

void World::Impl::end_actuators() {
  for (Actuator& a : actuators) a.visit([](auto& d) { d.end_step(); });
}

const World::Impl::Module& World::Impl::mod(int m) const {
  if (m < 0 || m >= static_cast<int>(modules.size()))
    throw std::out_of_range("module index " + std::to_string(m) + " out of range");
  return modules[m];
}

int World::Impl::actuator_index(int m, int s) const {
  const Module& md = mod(m);
  if (s < 0 || s >= static_cast<int>(md.driven.size()))
    throw std::out_of_range("servo " + std::to_string(s) + " of module " + std::to_string(m) +
                            " out of range");
  return md.driven[s];
}

int World::Impl::body_index(int m, int b) const {
  const Module& md = mod(m);
  if (b < 0 || b >= md.nbody)
    throw std::out_of_range("body " + std::to_string(b) + " of module " + std::to_string(m) +
                            " out of range");
  return md.body0 + b;
}

World::World(const WorldConfig& config, const ChainModel& chain) {
  if (config.dt_us <= 0) throw std::invalid_argument("dt_us must be > 0");
  if (chain.frames.size() != chain.modules.size())
    throw std::invalid_argument("the chain model's " + std::to_string(chain.modules.size()) + " modules have " +
                                std::to_string(chain.frames.size()) + " frames: compile it with compile_chain");
  impl_ = std::make_unique<Impl>(config.dt_us);
  impl_->build(config, chain);  // on a throw, ~Impl frees what was created
}

World::~World() = default;

int64_t World::degenerate_lcp_steps() const { return impl_->degenerate_lcp_steps; }

int World::module_count() const { return static_cast<int>(impl_->modules.size()); }
const std::string& World::module_type(int module) const { return impl_->mod(module).type; }
int World::servo_count(int module) const {
  return static_cast<int>(impl_->mod(module).driven.size());
}

ServoKind World::servo_kind(int module, int servo) const {
  return impl_->servo(module, servo).kind();
}

void World::set_servo_setpoint(int module, int servo, double setpoint) {
  impl_->actuators[impl_->actuator_index(module, servo)].visit(
      [&](auto& a) { a.set_setpoint(setpoint); });
}

void World::set_servo_setpoint_wire(int module, int servo, int32_t setpoint_wire) {
  impl_->actuators[impl_->actuator_index(module, servo)].visit([&](auto& a) {
    a.set_setpoint(std::decay_t<decltype(a)>::setpoint_from_wire(setpoint_wire));
  });
}

void World::set_servo_enabled(int module, int servo, bool enabled) {
  impl_->actuators[impl_->actuator_index(module, servo)].enabled = enabled;
}

void World::set_module_powered(int module, bool powered) {
  impl_->mod(module);
  impl_->modules[module].powered = powered;
}

// one physics step: ODE's demo loop with the actuator laws around it
void World::step() {
  Impl& w = *impl_;
  dAllocateODEDataForThread(dAllocateMaskAll);  // no-op once done for this thread
  w.begin_actuators();             // each actuator's torque or force law for this step
  dRandSetSeed(w.rand_seed);       // this world's random state (QuickStep reorders with it)
  w.contacts->collide(w.space);    // contact joints, touch flags
  w.wheels->begin_step();          // wheels and pads on the wall: contact joints
  if (w.exact) {
    const int64_t messages = t_lcp_messages;
    t_counting_lcp = true;
    dWorldStep(w.world, w.h);
    t_counting_lcp = false;
    if (t_lcp_messages != messages) ++w.degenerate_lcp_steps;
  } else {
    dWorldQuickStep(w.world, w.h);
  }
  w.rand_seed = dRandGetSeed();
  w.contacts->clear();
  w.wheels->end_step();            // their forces; their joints go
  w.end_actuators();               // currents and forces from the rates the step produced
  w.sensors.step_end(w.h);         // accelerometers, encoders
  w.time_us += w.dt_us;
}

int64_t World::time_us() const { return impl_->time_us; }
int64_t World::dt_us() const { return impl_->dt_us; }

void World::sample(int module, ModuleSample* out) const {
  const Impl::Module& md = impl_->mod(module);
  *out = ModuleSample{};
  out->n_servos = static_cast<int>(md.driven.size());
  out->n_adc = md.channels.n_adc;
  impl_->sensors.sample(module, md.powered, impl_->time_us, out);  // accelerometers, encoders
  if (!md.powered) return;
  sample_channels(md.channels, md.driven, impl_->actuators, *impl_->contacts, out);
}

uint16_t World::digital_inputs(int module) const {
  const Impl::Module& md = impl_->mod(module);
  return md.powered ? touch_inputs(md.channels, *impl_->contacts) : 0;
}

double World::module_supply_current_a(int module) const {
  const Impl::Module& md = impl_->mod(module);
  if (!md.powered) return 0.0;
  double sum = 0;
  for (int a : md.all)
    sum += impl_->actuators[a].visit([](const auto& x) { return x.supply_current_a(); });
  return sum;
}

Eigen::Vector3d World::chain_com() const {
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  double mass = 0;
  for (const Impl::Body& b : impl_->bodies) {
    acc += b.mass.mass * b.pose().translation();
    mass += b.mass.mass;
  }
  return mass > 0 ? Eigen::Vector3d(acc / mass) : Eigen::Vector3d::Zero();
}

int World::body_count(int module) const { return impl_->mod(module).nbody; }

const std::string& World::body_name(int module, int body) const {
  return impl_->bodies[impl_->body_index(module, body)].name;
}

World::BodyState World::body_state(int module, int body) const {
  const Impl::Body& part = impl_->bodies[impl_->body_index(module, body)];
  const dBodyID id = part.id;
  BodyState s;
  s.mass_kg = part.mass.mass;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s.inertia_kg_m2(r, c) = part.mass.I[r * 4 + c];
  const dReal* av = dBodyGetAngularVel(id);
  s.angular_velocity = Eigen::Vector3d(av[0], av[1], av[2]);
  dVector3 v;
  if (part.offset.matrix() == Eigen::Matrix4d::Identity()) {  // a body of its own: ODE's values as they are
    const dReal* p = dBodyGetPosition(id);
    const dReal* q = dBodyGetQuaternion(id);
    s.position = Eigen::Vector3d(p[0], p[1], p[2]);
    s.quaternion_wxyz = Eigen::Vector4d(q[0], q[1], q[2], q[3]);
    const dReal* lv = dBodyGetLinearVel(id);
    s.linear_velocity = Eigen::Vector3d(lv[0], lv[1], lv[2]);
    return s;
  }
  const Eigen::Isometry3d pose = part.pose();
  const Eigen::Quaterniond q(pose.linear());
  s.position = pose.translation();
  s.quaternion_wxyz = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
  const Eigen::Vector3d& r = part.offset.translation();
  dBodyGetRelPointVel(id, r.x(), r.y(), r.z(), v);
  s.linear_velocity = Eigen::Vector3d(v[0], v[1], v[2]);
  return s;
}

double World::servo_setpoint(int module, int servo) const {
  return impl_->servo(module, servo).visit([](const auto& a) { return a.setpoint(); });
}
double World::servo_position(int module, int servo) const {
  return impl_->servo(module, servo).visit([](const auto& a) { return a.position(); });
}
double World::servo_rate(int module, int servo) const {
  return impl_->servo(module, servo).visit([](const auto& a) { return a.rate(); });
}
double World::servo_current_a(int module, int servo) const {
  return impl_->servo(module, servo).visit([](const auto& a) { return a.current_a(); });
}
double World::servo_filtered_current_a(int module, int servo) const {
  return impl_->servo(module, servo).visit([](const auto& a) { return a.filtered_current_a(); });
}
double World::servo_effort(int module, int servo) const {
  return impl_->servo(module, servo).visit([](const auto& a) { return a.effort(); });
}

void World::pin_body(int module, int body) {
  dJointID j = dJointCreateFixed(impl_->world, nullptr);
  dJointAttach(j, impl_->bodies[impl_->body_index(module, body)].id, nullptr);
  dJointSetFixed(j);
}

void World::add_body_torque(int module, int body, const Eigen::Vector3d& torque_nm) {
  // a torque acts alike wherever on the (shared) body it is applied
  dBodyAddTorque(impl_->bodies[impl_->body_index(module, body)].id, torque_nm.x(), torque_nm.y(),
                 torque_nm.z());
}

void World::add_body_force(int module, int body, const Eigen::Vector3d& force_n) {
  const Impl::Body& part = impl_->bodies[impl_->body_index(module, body)];
  const Eigen::Vector3d p = part.pose().translation();  // the part's centre of mass
  dBodyAddForceAtPos(part.id, force_n.x(), force_n.y(), force_n.z(), p.x(), p.y(), p.z());
}

double World::max_docking_error_m() const {
  double worst = 0;
  const auto& mods = impl_->modules;
  const auto& bodies = impl_->bodies;
  for (size_t k = 0; k + 1 < mods.size(); ++k) {
    const Eigen::Vector3d a =
        (body_isometry(bodies[mods[k].back_body].id) * mods[k].back_in_body).translation();
    const Eigen::Vector3d b =
        (body_isometry(bodies[mods[k + 1].front_body].id) * mods[k + 1].front_in_body).translation();
    worst = std::max(worst, (a - b).norm());
  }
  return worst;
}

int World::dock_count() const { return static_cast<int>(impl_->docks.size()); }

World::DockForce World::dock_force(int dock) const {
  const Impl& w = *impl_;
  if (dock < 0 || dock >= static_cast<int>(w.docks.size()))
    throw std::out_of_range("dock " + std::to_string(dock) + " out of range (" + std::to_string(w.docks.size()) +
                            " docks as joints)");
  const Impl::Dock& d = w.docks[dock];
  const Impl::Module& ma = w.modules[dock];
  const Impl::Module& mb = w.modules[dock + 1];
  const Eigen::Isometry3d fa = body_isometry(w.bodies[ma.back_body].id) * ma.back_in_body;
  const Eigen::Isometry3d fb = body_isometry(w.bodies[mb.front_body].id) * mb.front_in_body;
  const Eigen::Vector3d x = fb.linear().col(0);
  // on body2 (module k + 1's front part): the ball's force acts at the
  // faces' centre, so the moment across the faces is the motor's alone
  const Eigen::Vector3d f(d.ball_fb.f2[0], d.ball_fb.f2[1], d.ball_fb.f2[2]);
  const Eigen::Vector3d t(d.motor_fb.t2[0], d.motor_fb.t2[1], d.motor_fb.t2[2]);
  DockForce out;
  out.axial_n = f.dot(x);
  out.shear_n = (f - out.axial_n * x).norm();
  out.twist_nm = t.dot(x);
  out.bend_nm = (t - out.twist_nm * x).norm();
  out.bend_deg = std::acos(std::clamp(fa.linear().col(0).dot(x), -1.0, 1.0)) * 180.0 / M_PI;
  return out;
}

World::Penetration World::deepest_contact() const {
  const Contacts::Deepest& d = impl_->contacts->deepest();
  if (d.body < 0) return {};
  const int m = impl_->contacts->module_of(d.body);  // its body indices are the World's
  return {d.depth_m, m, d.body - impl_->modules[m].body0};
}

int World::last_contact_count() const { return impl_->contacts->count() + impl_->wheels->on_count(); }

int World::wheel_count(int module) const { return impl_->wheels->count(module); }
const std::string& World::wheel_name(int module, int wheel) const {
  return impl_->wheels->name(module, wheel);
}
World::WheelState World::wheel_state(int module, int wheel) const {
  const WheelContacts::State& s = impl_->wheels->state(module, wheel);
  WheelState out;
  out.on = s.on;
  out.reach_m = s.reach_m;
  out.normal_n = s.normal_n;
  out.across_n = s.across_n;
  out.point = s.point;
  return out;
}

}  // namespace chainsim
