// Problem files: what they set, and errors that name file:line:column and the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <filesystem>
#include <fstream>

#include "optimize/individual_scene.h"
#include "optimize/problem.h"
#include "optimize/problem_params.h"
#include "scene/scene.h"
#include "temp_dir.h"

using namespace chainsim;

namespace {

// removed when the test program ends
std::string temp_dir() {
  static const chainsim_test::TempDir d("chainsim-problem-test");
  return d.path.string();
}

std::string write(const std::string& name, const std::string& text) {
  const std::string p = temp_dir() + "/" + name;
  std::ofstream(p) << text;
  return p;
}

const char* kBase = R"(name: base
duration_s: 1
chain: RRR
central:
  params: {gait: 1, amplitude_cdeg: 2000}
)";

const char* kPipeBase = R"(name: pipe
duration_s: 1
environment:
  type: pipe
  pipe:
    inner_diameter_m: 0.04
    segments:
      - {type: straight, length_m: 0.3}
      - {type: elbow, bend_radius_m: 0.08, angle_deg: 90, direction_deg: 90}
      - {type: straight, length_m: 0.3}
chain: TRRH
placement: {at: pipe_entry, inset_m: 0.01}
central: {params: {gait: 9}}
)";

std::string problem(const std::string& body) {
  write("base.yaml", kBase);
  write("pipe.yaml", kPipeBase);
  return write("p.yaml", body);
}

// the error of loading text, or "" when it loads
std::string error_of(const std::string& body) {
  try {
    load_problem_file(problem(body));
  } catch (const ProblemError& e) {
    return e.what();
  }
  return "";
}

const char* kGood = R"(name: good
scene: base.yaml
genome:
  params:
    - {target: central.amplitude_cdeg, min: 1000, max: 3000, step: 500}
    - {target: "chain[1].control_ms", min: 5, max: 20, step: 5}
measures:
  x: {kind: distance, along: x}
  e: {kind: energy}
objective:
  maximize: {x: 1, e: -0.01}
constraints:
  - {measure: x, min: 0}
ga: {population: 10, generations: 3, seed: 7, crossover: exponential}
evaluation: {duration_s: 0.5, trials: 3, fitness: quantile, quantile: 0.25, perturb: {along_m: 0.01, heading_deg: 5}}
)";

}  // namespace

TEST(Problem, LoadsEverySection) {
  const Problem pr = load_problem_file(problem(kGood));
  EXPECT_EQ(pr.name, "good");
  EXPECT_EQ(pr.scene_file, temp_dir() + "/base.yaml");
  EXPECT_EQ(pr.base_modules, 3);
  ASSERT_EQ(pr.genome.params.size(), 2u);
  EXPECT_EQ(pr.genome.params[1].scope, ParamGene::Scope::Module);
  EXPECT_EQ(pr.genome.params[1].module, 1);
  EXPECT_EQ(pr.genome.gene_upper(), (std::vector<int64_t>{4, 3}));
  ASSERT_EQ(pr.measures.size(), 2u);
  EXPECT_EQ(pr.measures[1].kind, MeasureSpec::Kind::Energy);
  EXPECT_TRUE(pr.objective.maximize);
  EXPECT_EQ(pr.objective.weights[1], (std::pair<int, double>{1, -0.01}));
  ASSERT_EQ(pr.constraints.size(), 1u);
  EXPECT_EQ(*pr.constraints[0].min, 0.0);
  EXPECT_EQ(pr.ga.population, 10);
  EXPECT_EQ(pr.ga.seed, 7u);
  EXPECT_EQ(pr.ga.crossover, "exponential");
  EXPECT_EQ(pr.evaluation.duration_s, 0.5);
  EXPECT_EQ(pr.evaluation.trials, 3);
  EXPECT_EQ(pr.evaluation.fitness, TrialFitness::Quantile);
  EXPECT_EQ(pr.evaluation.quantile, 0.25);
  EXPECT_EQ(pr.evaluation.perturb.along_m, 0.01);
  EXPECT_EQ(pr.evaluation.perturb.heading_deg, 5);
  EXPECT_TRUE(pr.evaluation.stop_when.empty());
  EXPECT_FALSE(pr.pipe);
}

TEST(Problem, DefaultsAreThePapersPopulation) {
  const Problem pr = load_problem_file(problem(R"(scene: base.yaml
genome: {params: [{target: central.amplitude_cdeg, min: 0, max: 10}]}
measures: {x: {kind: distance}}
objective: {maximize: x}
)"));
  EXPECT_EQ(pr.ga.population, 40);
  EXPECT_EQ(pr.ga.selection, "tournament");
  EXPECT_EQ(pr.genome.params[0].step, 1);
  EXPECT_EQ(pr.name, "p");
}

TEST(Problem, TheGenomeMakesTheIndividualsScene) {
  const Problem pr = load_problem_file(problem(kGood));
  const std::string text = individual_scene_yaml(pr, {"", {2500, 15}}, 42);
  const Scene s = load_scene_text(text, "individual");
  EXPECT_EQ(s.world.seed, 42u);
  EXPECT_EQ(s.duration_s, 0.5);
  EXPECT_EQ(s.central.params.at("amplitude_cdeg"), 2500);
  EXPECT_EQ(s.central.params.at("gait"), 1);           // the base scene's stay
  EXPECT_EQ(s.modules.at(1).params.at("control_ms"), 15);
  EXPECT_EQ(s.modules.at(0).params.count("control_ms"), 0u);
  EXPECT_EQ(s.modules.at(2).type, "rotation");
}

TEST(Problem, AChainGenomeWritesTheChainString) {
  const Problem pr = load_problem_file(problem(R"(scene: pipe.yaml
genome:
  chain: {positions: [T, RH, RH, RH], min_length: 2}
measures:
  out_s: {kind: time_to_reach, of: tail, along: pipe, reach_m: 0.55}
objective: {minimize: out_s, failed_fitness: 100}
)"));
  ASSERT_TRUE(pr.pipe);
  EXPECT_NEAR(pr.pipe->exit_m(), 0.6 + 0.08 * M_PI / 2, 1e-9);
  const std::string text = individual_scene_yaml(pr, {"TRH", {}}, 3);
  EXPECT_NE(text.find("chain: TRH"), std::string::npos) << text;
  EXPECT_EQ(load_scene_text(text, "individual").modules.size(), 3u);
}

// trials default to auto; a time_to_reach constraint's max becomes a
// stop_when rule every individual's scene carries, beside the problem's own
TEST(Problem, TrialsAutoAndTheStopsEveryIndividualCarries) {
  const Problem pr = load_problem_file(problem(R"(scene: pipe.yaml
genome:
  chain: {positions: [T, RH, RH, RH], min_length: 2}
measures:
  out_s: {kind: time_to_reach, of: tail, along: pipe, reach_m: 0.55}
objective: {minimize: out_s, failed_fitness: 100}
constraints:
  - {measure: out_s, max: 0.8}
evaluation:
  stop_when:
    - no_progress: {of: head, along: pipe, by_m: 0.004, within_s: 0.5}
)"));
  EXPECT_EQ(pr.evaluation.trials, 0);  // auto
  EXPECT_EQ(pr.evaluation.fitness, TrialFitness::Mean);
  ASSERT_EQ(pr.evaluation.stop_when.size(), 2u);
  EXPECT_EQ(pr.evaluation.stop_when[0].kind, StopRule::Kind::NoProgress);
  const StopRule& c = pr.evaluation.stop_when[1];
  EXPECT_EQ(c.kind, StopRule::Kind::NotReached);
  EXPECT_TRUE(c.tail);
  EXPECT_TRUE(c.along_pipe);
  EXPECT_EQ(c.reach_m, 0.55);
  EXPECT_EQ(c.by_s, 0.8);
  const Scene s = load_scene_text(individual_scene_yaml(pr, {"TRH", {}}, 3), "individual");
  ASSERT_EQ(s.stop_when.size(), 2u);
  EXPECT_EQ(s.stop_when[0].within_s, 0.5);
  EXPECT_EQ(s.stop_when[1].by_s, 0.8);
  // without the rule the constraint stays a check at the end
  const Problem off = load_problem_file(problem(R"(scene: pipe.yaml
genome: {chain: {positions: [T, RH]}}
measures: {out_s: {kind: time_to_reach, of: tail, along: pipe, reach_m: 0.55}}
objective: {minimize: out_s, failed_fitness: 100}
constraints: [{measure: out_s, max: 0.8}]
evaluation: {stop_on_constraints: false, trials: 2}
)"));
  EXPECT_TRUE(off.evaluation.stop_when.empty());
  EXPECT_EQ(off.evaluation.trials, 2);
  // nor when never reaching scores within the bound (never_s <= max)
  const Problem lenient = load_problem_file(problem(R"(scene: pipe.yaml
genome: {chain: {positions: [T, RH]}}
measures: {out_s: {kind: time_to_reach, of: tail, along: pipe, reach_m: 0.55, never_s: 0.5}}
objective: {minimize: out_s, failed_fitness: 100}
constraints: [{measure: out_s, max: 0.8}]
)"));
  EXPECT_TRUE(lenient.evaluation.stop_when.empty());
}

// the start pose moves within the problem's bounds, drawn from the trial's
// seed alone; in a pipe only deeper in and rolled. The exact solver and a
// target replace the scene's.
TEST(Problem, APerturbedStartIsTheTrialSeedsWithinTheBounds) {
  const Problem pr = load_problem_file(problem(R"(scene: base.yaml
genome: {params: [{target: central.amplitude_cdeg, min: 0, max: 10}]}
measures: {x: {kind: distance}}
objective: {maximize: x}
evaluation: {perturb: {along_m: 0.01, lateral_m: 0.005, heading_deg: 10, roll_deg: 3}}
)"));
  std::set<double> headings;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const StartPerturbation d = start_perturbation(pr, seed, false);
    EXPECT_LE(std::fabs(d.along_m), 0.01);
    EXPECT_LE(std::fabs(d.lateral_m), 0.005);
    EXPECT_LE(std::fabs(d.heading_deg), 10);
    EXPECT_LE(std::fabs(d.roll_deg), 3);
    headings.insert(d.heading_deg);
    const Scene s = load_scene_text(individual_scene_yaml(pr, {"", {5}}, seed), "individual");
    const Eigen::Vector3d off = s.world.head_position - Eigen::Vector3d(0, 0, 0.02);
    const double h = d.heading_deg * M_PI / 180;
    EXPECT_NEAR(s.world.heading_rad, h, 1e-12);
    EXPECT_NEAR(off.x(), d.along_m, 1e-6);  // base heading 0: along is x, sideways y
    EXPECT_NEAR(off.y(), d.lateral_m, 1e-6);
    EXPECT_NEAR(s.world.roll_rad, d.roll_deg * M_PI / 180, 1e-12);
    EXPECT_EQ(individual_scene_yaml(pr, {"", {5}}, seed), individual_scene_yaml(pr, {"", {5}}, seed));
  }
  EXPECT_GT(headings.size(), 15u);  // they do differ from trial to trial
  const Problem pipe = load_problem_file(problem(R"(scene: pipe.yaml
genome: {chain: {positions: [T, RH]}}
measures: {x: {kind: distance}}
objective: {maximize: x}
evaluation: {perturb: {along_m: 0.02, roll_deg: 5}}
)"));
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const StartPerturbation d = start_perturbation(pipe, seed, true);
    EXPECT_GE(d.along_m, 0);  // deeper in only
    EXPECT_LE(d.along_m, 0.02);
    const std::string text = individual_scene_yaml(pipe, {"TR", {}}, seed, "exact", "pic");
    const Scene s = load_scene_text(text, "individual");
    EXPECT_EQ(s.world.solver, WorldConfig::Solver::Exact);
    EXPECT_EQ(s.modules[0].target, Target::Pic);
    EXPECT_EQ(s.central.target, Target::Pic);
    EXPECT_NEAR(s.world.roll_rad, d.roll_deg * M_PI / 180, 1e-12);
  }
  const std::string e = error_of(R"(scene: pipe.yaml
genome: {chain: {positions: [T, RH]}}
measures: {x: {kind: distance}}
objective: {maximize: x}
evaluation: {perturb: {heading_deg: 5}}
)");
  EXPECT_NE(e.find("'evaluation.perturb.heading_deg': the base scene places the chain at the pipe's entry"),
            std::string::npos)
      << e;
}

// the individual's scene is written elsewhere (the search's work folder), so
// the programs the base scene names by relative path are made absolute from
// the base scene's folder, as loading the base scene resolves them; names
// stay names
TEST(Problem, ProgramPathsInTheIndividualsSceneAreTheBaseScenesOwn) {
  std::filesystem::create_directories(temp_dir() + "/sub/fw");
  write("sub/base.yaml", R"(name: rel
duration_s: 1
programs:
  rotation: {firmware: fw/rot}
chain:
  - {type: rotation}
  - {type: rotation, firmware: ./fw/mine}
  - {type: rotation, firmware: fw-rotation}
central: {program: ../sub/fw/central, params: {gait: 1}}
)");
  const Problem pr = load_problem_file(write("rel.yaml", R"(scene: sub/base.yaml
genome: {params: [{target: central.amplitude_cdeg, min: 0, max: 10}]}
measures: {x: {kind: distance}}
objective: {maximize: x}
)"));
  const Scene base = load_scene_text(pr.scene_text, pr.scene_file);
  const Scene s = load_scene_text(individual_scene_yaml(pr, {"", {5}}, 1), "/elsewhere/individual.yaml");
  const std::string fw = temp_dir() + "/sub/fw/";
  EXPECT_EQ(s.modules.at(0).firmware, fw + "rot");
  EXPECT_EQ(s.modules.at(1).firmware, fw + "mine");
  EXPECT_EQ(s.modules.at(2).firmware, "fw-rotation");
  EXPECT_EQ(s.central.firmware, fw + "central");
  for (size_t i = 0; i < 3; ++i)
    EXPECT_EQ(std::filesystem::path(base.modules[i].firmware).lexically_normal(),
              std::filesystem::path(s.modules[i].firmware).lexically_normal());
}

// program[NAME].param sets the parameter on every endpoint whose program has
// that file name, as written or as its module type's default, and on no other
TEST(Problem, AProgramTargetSetsEveryEndpointRunningThatProgram) {
  write("mixed.yaml", R"(name: mixed
duration_s: 1
chain:
  - {type: rotation, firmware: ../build/fw-mine}
  - {type: helicoidal}
  - {type: rotation}
  - {type: rotation, firmware: fw-mine}
central: {params: {gait: 1}}
)");
  const Problem pr = load_problem_file(write("prog.yaml", R"(scene: mixed.yaml
genome:
  params:
    - {target: "program[fw-mine].control_ms", min: 10, max: 40, step: 10}
    - {target: "program[fw-rotation].control_ms", min: 5, max: 15, step: 5}
measures: {x: {kind: distance}}
objective: {maximize: x}
)"));
  ASSERT_EQ(pr.genome.params.size(), 2u);
  EXPECT_EQ(pr.genome.params[0].scope, ParamGene::Scope::Program);
  EXPECT_EQ(pr.genome.params[0].program, "fw-mine");
  const Scene s = load_scene_text(individual_scene_yaml(pr, {"", {30, 5}}, 1), "/elsewhere/individual.yaml");
  auto param = [&](size_t i, const std::string& name) -> int64_t {
    const auto& ps = s.modules.at(i).params;
    return ps.count(name) ? ps.at(name) : -1;
  };
  EXPECT_EQ(param(0, "control_ms"), 30);  // ../build/fw-mine
  EXPECT_EQ(param(1, "control_ms"), -1);  // fw-helicoidal: neither
  EXPECT_EQ(param(2, "control_ms"), 5);   // fw-rotation, its type's default
  EXPECT_EQ(param(3, "control_ms"), 30);  // fw-mine
  EXPECT_EQ(s.central.params.count("control_ms"), 0u);
  // checked against the programs (as chainsim optimize does): a program no
  // endpoint runs is refused, naming the programs that run
  const auto check_error = [](const std::string& body) -> std::string {
    try {
      check_problem_params(load_problem_file(problem(body)), "");
    } catch (const ProblemError& e) {
      return e.what();
    }
    return "";
  };
  const std::string none = check_error(R"(scene: base.yaml
genome: {params: [{target: "program[fw-nothing].control_ms", min: 1, max: 10}]}
measures: {x: {kind: distance}}
objective: {maximize: x}
)");
  EXPECT_NE(none.find("no module and no central control runs a program named fw-nothing (they run: fw-rotation, "
                      "fw-central)"),
            std::string::npos)
      << none;
  // a letter in the middle of a chain position's choices is checked too: the
  // helicoidal program, only in the position's second letter, is a target
  EXPECT_EQ(check_error(R"(scene: base.yaml
genome:
  chain: {positions: [R, RHS]}
  params: [{target: "program[fw-helicoidal].control_ms", min: 5, max: 10}]
measures: {x: {kind: distance}}
objective: {maximize: x}
)"),
            "");
  // a malformed program name is the form's error
  EXPECT_NE(error_of(R"(scene: base.yaml
genome: {params: [{target: "program[fw/x].a", min: 0, max: 1}]}
measures: {x: {kind: distance}}
objective: {maximize: x}
)").find("program[PROGRAM].NAME"), std::string::npos);
}

TEST(Problem, EvaluationSeedsComeFromTheSearchSeedAndTheKeyOnly) {
  EXPECT_EQ(evaluation_seed(1, "THRH"), evaluation_seed(1, "THRH"));
  EXPECT_NE(evaluation_seed(1, "THRH"), evaluation_seed(2, "THRH"));
  EXPECT_NE(evaluation_seed(1, "THRH"), evaluation_seed(1, "THHR"));
  EXPECT_LT(evaluation_seed(99, "x"), uint64_t{1} << 62);
}

TEST(Problem, ErrorsNameFileLineColumnAndTheKey) {
  const std::string f = temp_dir() + "/p.yaml";
  // an unknown key, with the known ones
  EXPECT_EQ(error_of("scene: base.yaml\npopulation: 40\n"),
            f + ":2:1: unknown key 'population' in 'problem' (known: constraints, evaluation, ga, genome, measures, "
                "name, objective, scene, search)");
  EXPECT_EQ(error_of(std::string(kGood) + "  # trailing\n").empty(), true);
  // a bad letter in a chain position
  EXPECT_EQ(error_of(R"(scene: pipe.yaml
genome:
  chain: {positions: [T, RX]}
measures: {x: {kind: distance}}
objective: {maximize: x}
)"),
            f + ":3:26: 'genome.chain.positions[1]' has unknown module letter 'X' (T touch, R rotation, H helicoidal, "
                "S support, E extension, W traveller, P passive)");
  // a target of the wrong form
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome:
  params:
    - {target: amplitude_cdeg, min: 0, max: 10}
measures: {x: {kind: distance}}
objective: {maximize: x}
)"),
            f + ":4:16: 'genome.params[0].target' 'amplitude_cdeg' must be central.NAME, chain[INDEX].NAME, "
                "chain[*].NAME or program[PROGRAM].NAME (NAME: 1 to 15 letters, digits or _; PROGRAM: a program's "
                "file name, e.g. fw-rotation)");
  // a module index past the chain
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome:
  params:
    - target: chain[3].mode   # (in block style the brackets need no quotes)
      min: 0
      max: 10
measures: {x: {kind: distance}}
objective: {maximize: x}
)"),
            f + ":4:15: 'genome.params[0].target' 'chain[3].mode': the base scene's chain has modules 0..2");
  // max not on a step
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome:
  params:
    - {target: central.x, min: 0, max: 10, step: 3}
measures: {x: {kind: distance}}
objective: {maximize: x}
)"),
            f + ":4:40: 'genome.params[0].max' must be min plus a whole number of steps (0 + k * 3)");
  // the objective names a measure that does not exist
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome: {params: [{target: central.x, min: 0, max: 10}]}
measures: {x: {kind: distance}}
objective: {maximize: speed}
)"),
            f + ":4:23: 'objective.maximize' names measure 'speed', which is not in 'measures' (known: x)");
  // along the pipe without a pipe
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome: {params: [{target: central.x, min: 0, max: 10}]}
measures:
  s: {kind: distance, along: pipe}
objective: {maximize: s}
)"),
            f + ":4:30: 'measures.s.along' is pipe but the base scene's environment is not a pipe");
  // shortfall: reach_m is required, never_s belongs to time_to_reach only, not of the chain
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome: {params: [{target: central.x, min: 0, max: 10}]}
measures: {s: {kind: shortfall, of: tail}}
objective: {minimize: s, failed_fitness: 9}
)"),
            f + ":3:15: 'measures.s' needs 'reach_m' (the position along 'along' to reach, m)");
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome: {params: [{target: central.x, min: 0, max: 10}]}
measures: {s: {kind: shortfall, reach_m: 1, never_s: 3}}
objective: {minimize: s, failed_fitness: 9}
)"),
            f + ":3:45: unknown key 'never_s' in 'measures.s' (known: along, kind, of, reach_m)");
  // minimize without a failed fitness
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome: {params: [{target: central.x, min: 0, max: 10}]}
measures: {t: {kind: time_to_reach, reach_m: 0.3}}
objective: {minimize: t}
)"),
            f + ":4:12: 'objective' minimizes, so it needs 'failed_fitness' (a value worse than any real one)");
  // a value out of range
  EXPECT_EQ(error_of(R"(scene: base.yaml
genome: {params: [{target: central.x, min: 0, max: 10}]}
measures: {x: {kind: distance}}
objective: {maximize: x}
ga: {population: 1}
)"),
            f + ":5:18: 'ga.population' = 1 is out of range [2, 100000]");
  // a genome the base scene cannot take: more parameters than a program has room for
  std::string many = "scene: base.yaml\ngenome:\n  params:\n";
  for (int i = 0; i < 16; ++i) many += "    - {target: central.p" + std::to_string(i) + ", min: 0, max: 1}\n";
  many += "measures: {x: {kind: distance}}\nobjective: {maximize: x}\n";
  const std::string e = error_of(many);
  EXPECT_EQ(e.rfind(f + ":3:3: 'genome': the first individual's scene is not valid: ", 0), 0u) << e;
  EXPECT_NE(e.find("more than 16 parameters"), std::string::npos) << e;
  // the base scene's own error, inside the problem's
  write("broken.yaml", "chain: RRR\nduration_s: -1\n");
  const std::string b = error_of("scene: broken.yaml\n");
  EXPECT_EQ(b.rfind(f + ":1:8: 'scene': " + temp_dir() + "/broken.yaml:2:13: ", 0), 0u) << b;
  // YAML that does not parse
  EXPECT_EQ(error_of("scene: [base.yaml\n").rfind(f + ":2:1: ", 0), 0u);
  // the old name of trials, a quantile without its fitness, islands where there are none
  const std::string head = "scene: base.yaml\ngenome: {params: [{target: central.x, min: 0, max: 10}]}\n"
                           "measures: {x: {kind: distance}}\nobjective: {maximize: x}\n";
  EXPECT_EQ(error_of(head + "evaluation: {repeats: 3}\n"),
            f + ":5:23: 'evaluation.repeats' is now 'evaluation.trials' (the same: runs per individual, each with its "
                "own seed)");
  EXPECT_EQ(error_of(head + "evaluation: {quantile: 0.2}\n"),
            f + ":5:24: 'evaluation.quantile' applies to 'fitness: quantile' only");
  EXPECT_EQ(error_of(head + "evaluation: {trials: many}\n"), f + ":5:22: 'evaluation.trials' must be an integer");
  EXPECT_EQ(error_of(head + "search: exhaustive\nga: {islands: 4}\n"),
            f + ":6:15: 'ga.islands' applies to 'search: ga' (an exhaustive search has no populations)");
  EXPECT_EQ(error_of(head + "ga: {population: 4, migrants: 4}\n"),
            f + ":5:31: 'ga.migrants' (4) must be smaller than 'ga.population' (4)");
  // a key twice, a second document, an unsatisfiable constraint, a file that is not a regular one
  EXPECT_EQ(error_of(head + "measures: {y: {kind: energy}}\n").rfind(f + ":5:1: ", 0), 0u) << error_of(head + "measures: {y: {kind: energy}}\n");
  EXPECT_EQ(error_of(head + "---\nscene: base.yaml\n"), f + ":6:1: a second YAML document ('---'): a file holds one");
  EXPECT_NE(error_of(head + "constraints: [{measure: x, min: 5, max: -5}]\n").find("min 5.000000 is above max -5.000000: no run can keep it"),
            std::string::npos);
  try {
    load_problem_file("/dev/zero");
    ADD_FAILURE() << "/dev/zero was read as a problem file";
  } catch (const ProblemError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/dev/zero: ", 0), 0u) << e.what();
  }
  EXPECT_EQ(error_of(head + "evaluation: {stop_when: [{no_progress: {along: pipe, by_m: 1, within_s: 1}}]}\n"),
            f + ":5:48: 'evaluation.stop_when[0].no_progress.along' is pipe but the environment is not a pipe");
}

// the problems shipped in scenes/optimize load as they are; the other files
// there are base scenes of theirs
TEST(Problem, ShippedProblemsLoad) {
  const std::filesystem::path dir = std::filesystem::path(CHAINSIM_SOURCE_DIR) / "scenes" / "optimize";
  const std::vector<std::string> problems = {"elbow-configuration-100mm.yaml", "elbow-configuration.yaml",
                                             "elbow-configuration-travelling-bend.yaml", "minimal-configuration.yaml",
                                             "terrain-gait.yaml"};
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".yaml") files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    if (std::find(problems.begin(), problems.end(), f) == problems.end()) {
      EXPECT_NO_THROW(load_scene_file((dir / f).string()));
      continue;
    }
    Problem p;
    ASSERT_NO_THROW(p = load_problem_file((dir / f).string()));
    EXPECT_FALSE(p.measures.empty());
    EXPECT_FALSE(p.objective.weights.empty());
  }
  for (const std::string& f : problems) EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  // the elbow search ranks the chains that do not get through by their
  // shortfall: "never" scores the run's whole duration, so a chain that gets
  // through always beats one that does not
  for (const char* f :
       {"elbow-configuration.yaml", "elbow-configuration-100mm.yaml", "elbow-configuration-travelling-bend.yaml"}) {
    SCOPED_TRACE(f);
    const Problem e = load_problem_file((dir / f).string());
    ASSERT_EQ(e.measures[0].name, "through_s");
    EXPECT_EQ(e.measures[0].never_s, e.evaluation.duration_s);
    EXPECT_EQ(e.measures[1].kind, MeasureSpec::Kind::Shortfall);
    EXPECT_EQ(e.measures[1].reach_m, e.measures[0].reach_m);
    EXPECT_TRUE(e.constraints.empty());
  }
}

// the base scenes beside the problems are the shipped elbow scene with one
// thing changed and nothing else (problem files cannot override a scene, so
// each is a copy, and it must not drift from the original): the 100 mm
// elbow's bend radius, the travelling bend's bend_travel_ms
// (besides the turn: the search's variants give it, elbow_dir_deg 90, as
// their figures were found; the shipped scene senses it)
TEST(Problem, TheElbowVariantsAreTheShippedElbowSceneWithOneChange) {
  const std::string root = CHAINSIM_SOURCE_DIR;
  const std::string kGivenTurn =
      "    elbow_dir_deg: 90           # given: the search's figures were found so (docs/optimize.md)\n";
  auto body = [](const std::string& path) {  // the file without its comment lines
    std::ifstream in(path);
    std::string line, out;
    while (std::getline(in, line))
      if (line.rfind("#", 0) != 0) out += line + "\n";
    return out;
  };
  const std::string original = body(root + "/scenes/elbow-THRHRHRHH.yaml");
  using Edits = std::vector<std::pair<std::string, std::string>>;
  for (const auto& [file, edits] : std::vector<std::pair<std::string, Edits>>{
           {"elbow-100mm.yaml",
            {{"name: elbow-100mm\n", "name: elbow-THRHRHRHH\n"},
             {"bend_radius_m: 0.1,", "bend_radius_m: 0.08,"},
             {kGivenTurn, ""}}},
           {"elbow-travelling-bend.yaml",
            {{"name: elbow-travelling-bend\n", "name: elbow-THRHRHRHH\n"},
             {"    bend_travel_ms: 2000          # the bend travels down the chain: 2 s per place\n", ""},
             {kGivenTurn, ""}}}}) {
    SCOPED_TRACE(file);
    std::string copy = body(root + "/scenes/optimize/" + file);
    for (const auto& [from, to] : edits) {
      const size_t at = copy.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      copy.replace(at, from.size(), to);
    }
    EXPECT_EQ(copy, original);
  }
}
