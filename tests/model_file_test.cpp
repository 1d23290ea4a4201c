// A user's model read from files (study/plan/model_file.hpp): every refusal names the file, the key
// or line and the bad value; the paper's rod exported as a model (study/cli/model_export.hpp) runs
// the built-in rod's numbers bit for bit; the shipped block keeps the Signorini conditions after
// every step.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "core/methods/sparse_integrators.hpp"
#include "core/reference/exact_solution.hpp"
#include "core/run/references.hpp"
#include "core/run/simulation.hpp"
#include "same_run.hpp"
#include "study/cli/model_export.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/io/history_file.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/evaluation.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;
using testing::scratch_path;
using testing::write_file;

constexpr const char* kMass =
    "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 2.0\n2 2 2.0\n3 3 2.0\n";
constexpr const char* kStiffness =
    "%%MatrixMarket matrix coordinate real symmetric\n3 3 5\n1 1 10\n2 1 -10\n2 2 20\n3 2 -10\n"
    "3 3 10\n";

// A folder with M.mtx, K.mtx and scene.toml (`scene` after the [scene] header's defaults).
fs::path model_folder(const std::string& name, const std::string& scene,
                      const std::string& mass = kMass, const std::string& stiffness = kStiffness) {
  const fs::path dir = scratch_path("model_file", name);
  fs::create_directories(dir);
  write_file(dir / "M.mtx", mass);
  write_file(dir / "K.mtx", stiffness);
  write_file(dir / "scene.toml", scene);
  return dir / "scene.toml";
}

const std::string kGood =
    "[scene]\nkind = \"matrices\"\ndt = 1e-3\nt_end = 0.5\n"
    "[scene.matrices]\nmass = \"M.mtx\"\nstiffness = \"K.mtx\"\n"
    "[scene.initial]\nvelocity = { value = 1.0, dofs = \"all\" }\n"
    "[[scene.contact]]\nname = \"wall\"\ndof = 2\ngap = 0.1\n";

// The message of loading `scene` (with the matrices given), which must fail.
std::string refusal(const std::string& name, const std::string& scene,
                    const std::string& mass = kMass, const std::string& stiffness = kStiffness) {
  try {
    load_scene_file(model_folder(name, scene, mass, stiffness));
  } catch (const PlanError& e) {
    return e.what();
  }
  ADD_FAILURE() << name << ": loaded";
  return "";
}

TEST(ModelFile, ReadsAGoodModelAndRunsIt) {
  const SimulationSettings settings = load_scene_file(model_folder("good", kGood));
  ASSERT_TRUE(settings.model);
  const auto built = build(settings);
  ASSERT_TRUE(std::holds_alternative<Simulation>(built))
      << std::get<ParameterError>(built).constraint;
  const Simulation sim = std::get<Simulation>(built);
  EXPECT_EQ(sim.model()->model->size(), 3);
  EXPECT_EQ(sim.model()->model->contacts.front().plus, 2);
  SimulationWorkspace ws;
  const Evaluation e = evaluate(sim, ws);
  EXPECT_EQ(e.summary.status, RunStatus::ok) << e.summary.message;
  EXPECT_GE(e.reference_refinements, 1);  // converged: no history was given
}

TEST(ModelFile, RefusesEveryBadInputNamingIt) {
  const auto expect = [](const std::string& message, std::initializer_list<const char*> parts) {
    for (const char* part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  };
  expect(refusal("not_square", kGood,
                 "%%MatrixMarket matrix coordinate real general\n3 2 1\n1 1 2.0\n"),
         {"M.mtx", "not square", "3 rows, 2 columns"});
  expect(refusal("sizes", kGood, kMass,
                 "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 1 1.0\n"),
         {"K.mtx", "2 rows", "mass matrix has 3"});
  expect(refusal("not_a_number", kGood, kMass,
                 "%%MatrixMarket matrix coordinate real symmetric\n3 3 1\n1 1 abc\n"),
         {"K.mtx:3", "abc"});
  expect(refusal("not_symmetric", kGood, kMass,
                 "%%MatrixMarket matrix coordinate real general\n3 3 2\n1 2 1.0\n2 1 3.0\n"),
         {"K.mtx", "not symmetric", "(1, 2)"});
  expect(refusal("mass_not_pd", kGood,
                 "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 2.0\n2 2 -1.0\n"
                 "3 3 2.0\n"),
         {"M.mtx", "not positive definite", "at DOF 1", "row 2"});
  std::string scene = kGood;
  scene.replace(scene.find("dof = 2"), 7, "dof = 3");
  expect(refusal("dof_range", scene), {"scene.contact.1.dof", "DOF 3 is out of range", "0 to 2"});
  expect(refusal("two_walls",
                 kGood + "[[scene.contact]]\nname = \"floor\"\ndof = 2\nside = \"lower\"\n"),
         {"scene.contact.2.dof", "DOF 2 already has a wall", "\"wall\""});
  expect(refusal("side", kGood + "[[scene.contact]]\nname = \"x\"\ndof = 1\nside = \"up\"\n"),
         {"scene.contact.2.side", "\"up\""});
  expect(refusal("pair_side",
                 kGood + "[[scene.contact]]\nname = \"p\"\ndofs = [0, 1]\nside = \"upper\"\n"),
         {"scene.contact.2.side", "applies to a wall"});
  expect(refusal("no_contact", kGood.substr(0, kGood.find("[[scene.contact]]"))),
         {"scene.contact", "at least one"});
  expect(refusal("slice", "[scene.dof_sets]\nodd = \"1:x\"\n" + kGood),
         {"scene.dof_sets.odd", "1:x"});
  expect(refusal("no_dt", std::string(kGood).replace(kGood.find("dt = 1e-3\n"), 10, "")),
         {"dt", "time step"});
  expect(refusal("device", std::string(kGood).replace(kGood.find("\"K.mtx\""), 7, "\"/dev/zero\"")),
         {"/dev/zero", "not a regular file"});
  expect(refusal("primary", kGood + "primary_contact = \"nowhere\"\n"), {"nowhere"});
  expect(refusal("rod_key", kGood.substr(0, kGood.find("[scene.matrices]")) + "length = 3.0\n" +
                                kGood.substr(kGood.find("[scene.matrices]"))),
         {"length", "one-body rod"});
  // The rod's consistent mass would be ignored on a model: refused, pointing at the model's M.
  expect(refusal("rod_mass", kGood.substr(0, kGood.find("[scene.matrices]")) +
                                 "mass = \"consistent\"\n" +
                                 kGood.substr(kGood.find("[scene.matrices]"))),
         {"scene.mass = \"consistent\"", "[scene.matrices] mass"});
}

TEST(ModelFile, RefusesABadReferenceHistory) {
  const fs::path scene = model_folder("reference", kGood + "[scene.reference]\nfile = \"r.csv\"\n");
  write_file(scene.parent_path() / "r.csv",
             "t,wall.pressure,wall.velocity\n0.001,0,1\n0.002,x,1\n");
  try {
    load_scene_file(scene);
    ADD_FAILURE() << "loaded";
  } catch (const PlanError& e) {
    EXPECT_NE(std::string(e.what()).find("r.csv:3"), std::string::npos) << e.what();
  }
  // A history that ends before the run: not usable, the runs fail with the reason.
  write_file(scene.parent_path() / "r.csv",
             "t,wall.pressure,wall.velocity\n0.001,0,1\n0.002,0,1\n");
  const Simulation sim = std::get<Simulation>(build(load_scene_file(scene)));
  SimulationWorkspace ws;
  const Evaluation e = evaluate(sim, ws);
  EXPECT_EQ(e.summary.status, RunStatus::failed);
  EXPECT_NE(e.summary.message.find("covers t ="), std::string::npos) << e.summary.message;
}

// `scene = "FILE"` names a scene file at the top of a plan; written under [scene] (TOML makes it
// scene.scene) the refusal says where it belongs, and the same line at the top loads.
TEST(ModelFile, ASceneFileNamedUnderTheSceneTableIsSentToTheTop) {
  const fs::path scene = model_folder("misplaced_scene", kGood);
  const std::string study =
      "[method]\nname = \"hht\"\n[study]\nkind = \"list\"\n"
      "points = [{ alpha = -0.1 }]\n";
  write_file(scene.parent_path() / "good.toml",
             "name = \"good\"\nscene = \"scene.toml\"\n" + study);
  const Plan good = load_plan(scene.parent_path() / "good.toml");
  ASSERT_TRUE(good.base.model);
  EXPECT_EQ(good.base.model->model->size(), 3);

  write_file(scene.parent_path() / "misplaced.toml",
             "name = \"misplaced\"\n[scene]\nscene = \"scene.toml\"\n" + study);
  try {
    load_plan(scene.parent_path() / "misplaced.toml");
    ADD_FAILURE() << "loaded";
  } catch (const PlanError& e) {
    const std::string m = e.what();
    for (const char* part : {"misplaced.toml:3:", "scene.scene = \"scene.toml\"",
                             "top-level key scene = \"scene.toml\"",
                             "above the plan's first [table]", "not under [scene]"}) {
      EXPECT_NE(m.find(part), std::string::npos) << part << " in " << m;
    }
  }
}

// A reference history in HDF5: the CSV's columns as datasets give the same indicators; a run's
// own history file (`impactid simulate --history FILE.h5`, datasets pressure.<contact>) is a
// reference too, against which the same run has no error; bad files are refused by name.
TEST(ModelFile, ReadsAReferenceHistoryFromHdf5) {
  const fs::path scene =
      model_folder("reference_h5", kGood + "[scene.reference]\nfile = \"r.csv\"\n");
  const fs::path dir = scene.parent_path();
  std::string csv = "t,wall.pressure,wall.velocity\n";
  std::vector<double> t, p, v;
  for (int i = 1; i <= 500; ++i) {
    t.push_back(i * 1e-3);
    p.push_back(i > 100 && i < 200 ? 1.0 + 1e-3 * i : 0.0);
    v.push_back(i < 100 ? 1.0 : -0.5);
    csv += std::to_string(t.back()) + "," + std::to_string(p.back()) + "," +
           std::to_string(v.back()) + "\n";
  }
  write_file(dir / "r.csv", csv);
  const Simulation from_csv = std::get<Simulation>(build(load_scene_file(scene)));
  {  // the CSV's numbers as text, read back
    std::vector<double> tc, pc, vc;
    for (const auto& sample : from_csv.model()->model->reference->t) tc.push_back(sample);
    Hdf5Writer h5(dir / "r.h5");
    h5.dataset("t", tc, Hdf5Dims{tc.size()});
    h5.dataset("wall.pressure", from_csv.model()->model->reference->contacts[0].pressure,
               Hdf5Dims{tc.size()});
    h5.dataset("wall.velocity", from_csv.model()->model->reference->contacts[0].velocity,
               Hdf5Dims{tc.size()});
    h5.commit();
  }
  write_file(scene, kGood + "[scene.reference]\nfile = \"r.h5\"\n");
  Simulation from_h5 = std::get<Simulation>(build(load_scene_file(scene)));
  from_h5.run.record_history = true;  // as `impactid simulate --history` does
  SimulationWorkspace wc, wh;
  const Evaluation ec = evaluate(from_csv, wc), eh = evaluate(from_h5, wh);
  ASSERT_EQ(eh.summary.status, RunStatus::ok) << eh.summary.message;
  EXPECT_EQ(eh.reference_refinements, -1);
  EXPECT_NE(eh.reference.find("r.h5"), std::string::npos) << eh.reference;
  EXPECT_TRUE(testing::same(ec.indicators.eps_p, eh.indicators.eps_p));
  EXPECT_TRUE(testing::same(ec.indicators.eps_v, eh.indicators.eps_v));
  EXPECT_GT(eh.indicators.eps_p, 0.1);  // the made-up history is not the run

  // The run's own history as its reference: no error.
  write_history(dir / "own.h5", from_h5, wh.trace, &*wh.model_reference);
  write_file(scene, kGood + "[scene.reference]\nfile = \"own.h5\"\n");
  const Simulation own = std::get<Simulation>(build(load_scene_file(scene)));
  SimulationWorkspace wo;
  const Evaluation eo = evaluate(own, wo);
  ASSERT_EQ(eo.summary.status, RunStatus::ok) << eo.summary.message;
  EXPECT_EQ(eo.indicators.eps_p, 0.0);
  EXPECT_EQ(eo.indicators.eps_v, 0.0);

  // Refusals: no t, lengths that disagree, no contact's dataset, an unknown extension.
  const auto refused = [&](const std::string& file, const std::string& expected) {
    write_file(scene, kGood + "[scene.reference]\nfile = \"" + file + "\"\n");
    try {
      load_scene_file(scene);
      ADD_FAILURE() << file << ": loaded";
    } catch (const PlanError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("reference.file"), std::string::npos) << e.what();
    }
  };
  const std::vector<double> three{1e-3, 2e-3, 3e-3}, two{1.0, 2.0};
  {
    Hdf5Writer h5(dir / "no_t.h5");
    h5.dataset("wall.pressure", three, Hdf5Dims{3});
    h5.commit();
    Hdf5Writer short_h5(dir / "short.h5");
    short_h5.dataset("t", three, Hdf5Dims{3});
    short_h5.dataset("pressure.wall", two, Hdf5Dims{2});
    short_h5.commit();
    Hdf5Writer none(dir / "none.h5");
    none.dataset("t", three, Hdf5Dims{3});
    none.dataset("floor.pressure", three, Hdf5Dims{3});
    none.commit();
  }
  refused("no_t.h5", "no_t.h5: has no dataset t");
  refused("short.h5", "pressure.wall has 2 samples, t has 3");
  refused("none.h5", "has no dataset <contact>.pressure");
  refused("r.txt", "unknown format");
  refused("missing.h5", "missing.h5: no such file");
}

// The converged reference's method and its number of halvings are settings
// (reference_method, reference_max_refinements); the description says which method ran.
TEST(ModelReference, ItsMethodAndHalvingsAreSettings) {
  SimulationSettings settings = load_scene_file(model_folder("reference_method", kGood));
  const Simulation automatic = std::get<Simulation>(build(settings));
  EXPECT_EQ(kind_of(reference_options(automatic).method), MethodKind::central_difference);
  EXPECT_EQ(reference_options(automatic).max_refinements, 10);
  ASSERT_FALSE(assign_text(settings, "reference_method", "hht"));
  ASSERT_FALSE(assign_text(settings, "reference_max_refinements", "2"));
  ASSERT_FALSE(assign_text(settings, "reference_tolerance", "1e-9"));  // not reachable in 2
  const Simulation hht = std::get<Simulation>(build(settings));
  EXPECT_EQ(kind_of(reference_options(hht).method), MethodKind::hht);
  SimulationWorkspace ws;
  const Evaluation e = evaluate(hht, ws);
  EXPECT_EQ(e.reference_refinements, 2);
  EXPECT_EQ(e.reference.find("not converged: hht at dt/4"), 0U) << e.reference;
  EXPECT_EQ(*numeric_value(hht, "reference_max_refinements"), 2.0);

  ASSERT_FALSE(assign_text(settings, "reference_method", "auto"));
  EXPECT_EQ(kind_of(reference_options(std::get<Simulation>(build(settings))).method),
            MethodKind::central_difference);
  const auto error = assign_text(settings, "reference_method", "rk4");
  ASSERT_TRUE(error);
  EXPECT_EQ(error->value, "rk4");
  ASSERT_FALSE(assign_text(settings, "reference_max_refinements", "0"));
  const auto built = build(settings);
  const auto* bad = std::get_if<ParameterError>(&built);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->field, "reference_max_refinements");
  EXPECT_EQ(bad->value, "0");
}

// The rod exported as a model: the same run, bit for bit (lumped and consistent mass, with and
// without stiffness damping), and the same indicators against its exported exact solution.
TEST(ModelExport, TheExportedRodRunsTheBuiltInRodBitForBit) {
  for (const MassMatrix mass : {MassMatrix::lumped, MassMatrix::consistent}) {
    for (const double damping : {0.0, 2e-8}) {
      SimulationSettings settings;
      settings.scene.mass = mass;
      settings.scene.rayleigh_stiffness = damping;
      settings.scene.elements = 60;
      const Simulation rod = std::get<Simulation>(build(settings));
      const fs::path dir = scratch_path("model_export", "rod");
      export_model(rod, dir);
      SimulationSettings model_settings = load_scene_file(dir / "scene.toml");
      for (const MethodParams& method :
           {MethodParams{HhtParams{.alpha = -0.2}}, MethodParams{CentralDifferenceParams{}},
            MethodParams{NewmarkParams{.delta = 0.3}}}) {
        const std::string name = std::string(to_string(mass)) + " a1=" + std::to_string(damping) +
                                 " " + to_string(kind_of(method));
        Simulation a = rod, b = std::get<Simulation>(build(model_settings));
        a.method = b.method = method;
        SimulationWorkspace wa, wb;
        const Evaluation ea = evaluate(a, wa), eb = evaluate(b, wb);
        testing::expect_same_samples(wb.trace.pressure, wa.trace.pressure, name + " pressure");
        testing::expect_same_samples(wb.trace.velocity, wa.trace.velocity, name + " velocity");
        EXPECT_EQ(ea.summary.status, eb.summary.status) << name;
        if (damping == 0.0) {  // the exact solution is the model's reference
          EXPECT_TRUE(testing::same(ea.indicators.eps_p, eb.indicators.eps_p)) << name;
          EXPECT_TRUE(testing::same(ea.indicators.eps_v, eb.indicators.eps_v)) << name;
          EXPECT_TRUE(testing::same(ea.indicators.nop_p, eb.indicators.nop_p)) << name;
          EXPECT_TRUE(testing::same(ea.indicators.nop_v, eb.indicators.nop_v)) << name;
          EXPECT_EQ(eb.reference_refinements, -1) << name;
        }
      }
    }
  }
}

// The bouncing bar under gravity exported as a model: its load and potential as f.mtx and
// [scene.load], its exact solution as the reference; the model runs the scene bit for bit (the
// model of tridiagonal matrices takes the scene's own system and load), with the same indicators.
TEST(ModelExport, TheExportedBouncingBarFallsAndBouncesAsTheScene) {
  SimulationSettings settings =
      load_scene_file(fs::path(IMPACTID_SOURCE_DIR) / "plans/bouncing-bar.toml");
  ASSERT_TRUE(settings.bodies.has_value());
  settings.bodies->bodies[0].segments[0].elements = 40;
  settings.bodies->t_end = 6.0;
  const Simulation scene = std::get<Simulation>(build(settings));
  const fs::path dir = scratch_path("model_export", "bouncing");
  export_model(scene, dir);
  ASSERT_TRUE(fs::exists(dir / "f.mtx"));
  const SimulationSettings model_settings = load_scene_file(dir / "scene.toml");
  ASSERT_TRUE(model_settings.model.has_value());
  EXPECT_NEAR(model_settings.model->model->load.rest_potential, 1000.0, 1e-9);
  EXPECT_NEAR(model_settings.model->model->load.force.sum(), -100.0, 1e-12);
  for (const MethodParams& method :
       {MethodParams{HhtParams{.alpha = -0.3}}, MethodParams{CentralDifferenceParams{}},
        MethodParams{KimExplicitParams{}}}) {
    const std::string name = to_string(kind_of(method));
    Simulation a = scene, b = std::get<Simulation>(build(model_settings));
    a.method = b.method = method;
    SimulationWorkspace wa, wb;
    const Evaluation ea = evaluate(a, wa), eb = evaluate(b, wb);
    ASSERT_EQ(ea.summary.status, RunStatus::ok) << name << ": " << ea.summary.message;
    EXPECT_EQ(eb.summary.status, RunStatus::ok) << name << ": " << eb.summary.message;
    testing::expect_same_samples(wb.trace.pressure, wa.trace.pressure, name + " pressure");
    testing::expect_same_samples(wb.trace.velocity, wa.trace.velocity, name + " velocity");
    EXPECT_TRUE(testing::same(ea.summary.final_energy, eb.summary.final_energy)) << name;
    EXPECT_TRUE(testing::same(ea.indicators.eps_p, eb.indicators.eps_p)) << name;
    EXPECT_TRUE(testing::same(ea.indicators.nop_p, eb.indicators.nop_p)) << name;
    EXPECT_EQ(eb.reference_refinements, -1) << name;  // the exported exact history
  }
}

// The shipped plans on models load, and the Fig. 4 plan on the exported rod gives the built-in
// plan's numbers point for point (a quarter of its points: the whole is `impactid run`'s).
TEST(ModelExample, TheShippedPlansLoadAndTheRodPlanEqualsTheBuiltInOne) {
  const fs::path root(IMPACTID_SOURCE_DIR);
  for (const char* plan :
       {"examples/block/hht-delta-alpha.toml", "examples/block/identical-dissipation.toml",
        "examples/block/work-precision.toml"}) {
    EXPECT_NO_THROW(load_plan(root / plan)) << plan;
  }
  const Plan model = load_plan(root / "examples/rod/hht-delta-alpha.toml");
  const Plan builtin = load_plan(root / "plans/hht-delta-alpha.toml");
  const PointSet a(model), b(builtin);
  ASSERT_EQ(a.size(), b.size());
  SimulationWorkspace wa, wb;
  for (long i = 0; i < a.size(); i += 4) {
    const Evaluation ea = evaluate(std::get<Simulation>(build(a.settings(i))), wa);
    const Evaluation eb = evaluate(std::get<Simulation>(build(b.settings(i))), wb);
    ASSERT_EQ(ea.summary.status, eb.summary.status) << i;
    for (const auto& [x, y] : {std::pair{ea.indicators.eps_p, eb.indicators.eps_p},
                               {ea.indicators.eps_v, eb.indicators.eps_v},
                               {ea.indicators.nop_p, eb.indicators.nop_p},
                               {ea.indicators.nop_v, eb.indicators.nop_v},
                               {ea.indicators.p_max, eb.indicators.p_max}}) {
      ASSERT_TRUE(testing::same(x, y)) << "point " << i << ": " << x << " vs " << y;
    }
  }
}

// Without its exact solution, the exported rod's reference is the converged one: central
// difference (M is lumped) at dt/2^k. It converges to its tolerance; what it converges to is the
// semi-discrete rod's solution, which approaches the exact one as the mesh is refined (measured:
// eps of the reference against the exact solution: pressure 2.7 %, 0.87 %, 0.25 %
// and velocity 16 %, 9.1 %, 5.0 % for 50, 200 and 800 elements).
TEST(ModelReference, TheRodsConvergedReferenceApproachesTheExactSolutionWithTheMesh) {
  double previous_eps_p = 1.0, previous_eps_v = 1.0;
  for (const int elements : {50, 200}) {
    SimulationSettings settings;
    settings.scene.elements = elements;
    const Simulation rod = std::get<Simulation>(build(settings));
    const fs::path dir = scratch_path("model_reference", "rod" + std::to_string(elements));
    export_model(rod, dir);
    std::string scene;
    {
      std::ifstream in(dir / "scene.toml");
      scene.assign(std::istreambuf_iterator<char>(in), {});
    }
    write_file(dir / "scene.toml", scene.substr(0, scene.find("[scene.reference]")));
    const Simulation model = std::get<Simulation>(build(load_scene_file(dir / "scene.toml")));
    const ModelReference r =
        model_reference(*model.model(), model_reference_defaults(*model.model()->model));
    ASSERT_TRUE(r.converged) << r.description();
    EXPECT_LT(r.change, 1e-3);
    EXPECT_EQ(kind_of(r.options.method), MethodKind::central_difference);
    const RodImpactExact exact(*rod.rod());
    double dp = 0, sp = 0, dv = 0, sv = 0;
    for (std::size_t i = 0; i < r.contacts[0].pressure.size(); ++i) {
      const ContactNodeValues e = exact.at_sample(static_cast<long>(i) + 1);
      dp += std::abs(r.contacts[0].pressure[i] - e.pressure);
      sp += std::abs(e.pressure);
      dv += std::abs(r.contacts[0].velocity[i] - e.velocity);
      sv += std::abs(e.velocity);
    }
    const double eps_p = dp / sp, eps_v = dv / sv;
    EXPECT_LT(eps_p, 0.6 * previous_eps_p) << elements;
    EXPECT_LT(eps_v, 0.8 * previous_eps_v) << elements;
    previous_eps_p = eps_p;
    previous_eps_v = eps_v;
  }
  EXPECT_LT(previous_eps_p, 0.01);  // 200 elements: within 1 % of the exact pressure
}

// The shipped block (examples/block: 1722 DOFs, 41 contacts on its bottom edge), stepped by the
// sparse integrators: after every step every multiplier is >= 0, no node is below the plane by
// more than the solver's tolerance, and a pushing node is exactly on it.
TEST(ModelExample, TheBlockKeepsTheSignoriniConditionsAfterEveryStep) {
  const Simulation sim = std::get<Simulation>(
      build(load_scene_file(fs::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*sim.model());
  ASSERT_TRUE(scene.sparse);
  const SparseSystem& system = *scene.sparse;
  for (const MethodParams& method :
       {MethodParams{HhtParams{.alpha = -0.1}}, MethodParams{CentralDifferenceParams{}}}) {
    State s;
    s.u = Eigen::VectorXd::Zero(system.size());
    s.v = scene.initial_velocity;
    s.a = Eigen::VectorXd::Zero(system.size());
    s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
    SparseImplicitIntegrator implicit;
    SparseCentralDifference explicit_;
    const bool cdm = std::holds_alternative<CentralDifferenceParams>(method);
    ASSERT_TRUE(cdm ? explicit_.initialize(system, CdmVelocity::central, scene.dt, s)
                    : implicit.initialize(system, implicit_coefficients(method), scene.dt));
    long pushing = 0;
    for (long i = 0; i < scene.step_count; ++i) {
      if (cdm) {
        explicit_.step(system, s);
      } else {
        implicit.step(system, s);
      }
      for (std::size_t k = 0; k < system.constraints.size(); ++k) {
        const Constraint& c = system.constraints[k];
        const double lambda = s.multipliers[static_cast<Eigen::Index>(k)];
        const double gap = c.gap + s.u[c.minus];  // a lower wall: u >= −gap
        ASSERT_GE(lambda, 0.0) << "step " << i;
        ASSERT_GE(gap, -1e-12 * c.gap) << "step " << i << " contact " << k;
        if (lambda > 0.0) {
          ++pushing;
          // Complementarity: on the plane at the end of the step where the implicit multiplier
          // acts (central difference's λ_t acts on u_{t+Δt}, one sample later than `s`).
          if (!cdm) {
            ASSERT_EQ(s.u[c.minus], -c.gap) << "step " << i;
          }
        }
      }
    }
    EXPECT_GT(pushing, 100) << to_string(kind_of(method));
  }
}

}  // namespace
}  // namespace impactid
