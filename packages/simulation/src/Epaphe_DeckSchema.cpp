#include "Epaphe_DeckSchema.hpp"

#include "Epaphe_ThermalParameters.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ModelImporter.hpp"
#include "Epaphe_BuiltInMeshes.hpp"
#include "Epaphe_ReductionMethod.hpp"
#include "Epaphe_ObserverKind.hpp"
#include "Epaphe_SurfaceContact.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_LoadTimeFunction.hpp"

#include <Teuchos_XMLParameterListHelpers.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

namespace epaphe {

using namespace deck;

namespace {

/// Run: what the run is called and how it uses the machine.
void addRunParameters(Teuchos::ParameterList& pl) {
  auto& run = pl.sublist("Run", false, "What the run is called and how it uses the machine");
  addString(run, "Name", "epaphe", "Name of the run, printed and stored in the output");
  addInt(run, "Threads", 1,
         "OpenMP threads of the Kokkos kernels (0: OMP_NUM_THREADS, else all cores); the "
         "command line option --threads overrides it. A loop of less than 20 us of work runs on "
         "one thread whatever this says (EPAPHE_SERIAL_WORK_NS), so 2 threads are never much "
         "slower than 1; they pay off where a step has much contact work (the cube between two "
         "flexible rings: 1.5x)",
         0, 1024);
  addBool(run, "Adaptive threads", true,
          "With more than one thread: time the step's loops on the thread team against the calling "
          "thread alone while the run runs (alternating blocks of steps), run the faster, and time "
          "them again now and then (the machine's load may change); when other processes' threads "
          "already hold the cores the team would need (Linux /proc), the calling thread without timing "
          "the team. The results are the same bits either way (Epaphe_ParallelChooser.hpp)");
  addDouble(run, "Progress interval", 2.0, "Wall-clock seconds between progress lines (0: none)", 0.0);
  addBool(run, "Divergence step check", true,
          "When a run stops with its energy growing without bound, run the deck "
          "again at half the time step up to twice the stop time (one MPI rank, "
          "a scratch output) and say whether the step changes the divergence "
          "(docs/user/divergence.md)");
}

/// Bodies-><name>->Mesh: the body's finite-element mesh, by the importer 'Type' names among the
/// registered ones (Epaphe_ModelImporter.hpp), and every importer's keys.
void addMeshParameters(Teuchos::ParameterList& body) {
  auto& mesh = body.sublist("Mesh", false, "The body's finite-element mesh");
  const std::vector<std::string> names = ImporterRegistry::names();
  std::vector<int> values;
  std::string doc;
  for (const std::string& name : names) {
    values.push_back(static_cast<int>(values.size()));
    doc += (doc.empty() ? "" : ". ") + name + ": " + ImporterRegistry::make(name, "the deck schema")->documentation();
  }
  addEnum(mesh, "Type", "Box", names, values, doc);
  mesh.setParameters(*importerParameters());
}

/// Bodies-><name>->Reduction: the model reduction (thesis section 2.3): 'Method' among the registered
/// methods (Epaphe_ReductionMethod.hpp), each method's own keys, and the keys of every method.
void addReductionParameters(Teuchos::ParameterList& body) {
  auto& red = body.sublist("Reduction", false, "Model reduction (thesis section 2.3)");
  const std::vector<std::string> names = ReductionRegistry::names();
  std::vector<int> values;
  std::string doc;
  std::vector<Teuchos::RCP<const Teuchos::ParameterList>> keys;
  for (const std::string& name : names) {
    const auto method = ReductionRegistry::make(name, "the deck schema");
    values.push_back(static_cast<int>(values.size()));
    doc += (doc.empty() ? "" : "; ") + name + ": " + method->documentation();
    keys.push_back(method->getValidParameters());
  }
  addEnum(red, "Method", "Craig-Bampton", names, values, doc);
  for (const auto& k : keys) red.setParametersNotAlreadySet(*k);
  addString(red, "Retained node set", "", "Nodes kept as physical DOFs (empty: the contact node set)");
  addBool(red, "Cache", true,
          "Store the reduced model in HDF5 and reuse it while the model and reduction "
          "parameters are unchanged");
  addString(red, "Cache file", "", "Cache path (empty: <output file stem>.<body>.rom.h5)");
}

/// Bodies: one sublist per flexible body (mesh, material, boundary conditions, contact nodes, reduction).
void addBodyParameters(Teuchos::ParameterList& pl) {
  auto& body = pl.sublist("Bodies", false, "One sublist per flexible body, named by the user")
                   .sublist("*", false, "A flexible body: mesh, material, reduction, contact nodes");
  addMeshParameters(body);
  auto& mat = body.sublist(
      "Material", false,
      "Isotropic linear elastic material of the built-in meshes (unused, and optional, for imported models)");
  addDouble(mat, "Density", 7800, "Mass density (kg/m^3)", 1e-300);
  addDouble(mat, "Young's modulus", 2.1e11, "Young's modulus (Pa)", 1e-300);
  addDouble(mat, "Poisson's ratio", 0.3, "Poisson's ratio", -0.999999, 0.499999);
  addEnum(mat, "Element formulation", "Full integration", {"Full integration", "Incompatible modes"}, {0, 1},
          "The hexahedra's stiffness: Full integration (trilinear, 2x2x2 Gauss points; stiff in bending "
          "with few elements through a thickness) or Incompatible modes (nine condensed bubble modes per "
          "element: bending without parasitic shear, for thin rings, casings and blades)");
  addString(body, "Clamped node set", "",
            "Node set fixed in all directions (empty: none); built-in meshes only (an "
            "imported model carries its own boundary conditions)");
  addDoubleArray(body, "Initial velocity", {0, 0, 0},
                 "Uniform initial velocity of the body (m/s); a Massless "
                 "boundary model takes its projection onto the modes");
  addDoubleArray(body, "Gravity", {0, 0, 0},
                 "Uniform acceleration of gravity on the body (m/s^2), e.g. {0, 0, -9.81}: the constant reduced "
                 "force f = sum_d g_d T^T M e_d, exact when a rigid translation is a motion of the model (a body "
                 "without clamps, any reduction) or the mass is lumped (Full, lumped mass); "
                 "refused otherwise. Its work is the run's external work in the energy balance");
  addString(body, "Contact node set", "", "Nodes checked against every surface (empty: no contact)");
  addStringArray(body, "Watched node sets", {}, "Node sets whose displacement and velocity are written");
  auto& inst = body.sublist("Instances", false,
                            "Copies of the body around the engine axis (a bladed stage on a rigid disk): one "
                            "reduction, N bodies named <body>[k] that share its reduced model (docs/user/stage.md)");
  addInt(inst, "Count", 1,
         "N: instance k stands at 2 pi k / N about each surface's 'Rotation axis' (its copy of every surface "
         "is turned back by that angle); 1: the body alone",
         1, 100000);
  addDoubleArray(inst, "Stiffness factors", {},
                 "Mistuning: instance k's stiffness is factor_k K (its frequencies sqrt(factor_k) times the "
                 "tuned ones), N values > 0 (empty: tuned, or the random pattern below)");
  addDouble(inst, "Mistuning standard deviation", 0.0,
            "A random mistuning pattern: factor_k = 1 + delta_k, delta_k normal with this standard deviation "
            "(Box-Muller on a 64-bit Mersenne Twister seeded by 'Seed': the same pattern on every machine)",
            0.0, 0.3);
  addInt(inst, "Seed", 1, "Seed of the random mistuning pattern", 0, 2147483647);
  addThermalParameters(body);
  auto& load =
      body.sublist("Loads", false, "External forces on the body's nodes, one sublist per load, named by the user")
          .sublist("*", false,
                   "A force F g(t) on every node of a node set, projected onto the model as R^T F "
                   "(docs/theory/forced-response.md, eqs. 65-67); its work is the run's external work");
  addString(load, "Node set", "",
            "The nodes the force acts on (a named node set or a union \"a, b\"; required without 'Reduced DOFs')");
  addDoubleArray(load, "Force", {0, 0, 0}, "F: the force on each node of the set (N), times the time function g(t)");
  addIntArray(
      load, "Reduced DOFs", {},
      "Instead of a node set: the coordinates q_j of the body's model the load acts on, numbered from 0 in "
      "the model's order (Craig-Bampton and massless boundary: the retained DOFs first, x, y, z of each retained "
      "node in the order of 'retainedNodes' in its reduced-model cache, then the modes; a full model: its "
      "free DOFs)");
  addDoubleArray(load, "Reduced forces", {},
                 "With 'Reduced DOFs': the force f_j on each of them (N on a physical DOF, the modal force on a "
                 "mode), times the time function g(t)");
  addEnum(load, "Time function", "Constant", loadTimeKindNames(), {0, 1, 2, 3},
          "g(t): Constant, g = 1; Harmonic, g = cos(2 pi Frequency t + Phase); Table, g linear between the "
          "points (Times, Values), held at the first and last values outside them; Ramp, g = min(t / Ramp time, 1)");
  addDouble(load, "Frequency", 0.0, "Harmonic: the frequency (Hz), > 0", 0.0);
  addDouble(load, "Phase", 0.0, "Harmonic: the phase at t = 0 (rad)");
  addDoubleArray(load, "Times", {}, "Table: the times (s), increasing");
  addDoubleArray(load, "Values", {}, "Table: g at each of 'Times'");
  addDouble(load, "Ramp time", 0.0, "Ramp: the time T (s) g takes to rise from 0 to 1, > 0", 0.0);
  auto& rot = body.sublist("Rotation", false,
                           "The body turns at a steady speed and is modelled in its own frame, "
                           "where the centrifugal load is static (the casing turns around it)");
  addDouble(rot, "Speed", 0.0,
            "Omega (rad/s) about the Axis; 0: the body at rest. Built-in meshes: the model is "
            "the tangent at the centrifugal static state ('Static state'), K_e + K_sigma - "
            "Omega^2 M_perp, and the nodes start at their static position (the tip growth)");
  addDoubleArray(rot, "Axis", {0, 0, 1}, "Direction of the rotation axis (need not be unit)");
  addDoubleArray(rot, "Axis point", {0, 0, 0}, "A point of the rotation axis (m)");
  addDoubleArray(rot, "Speed range", {},
                 "{minimum, maximum} (rad/s): build one parametric reduced model over "
                 "the range from Craig-Bampton (or massless-boundary) reductions at 'Sample "
                 "speeds' and take the "
                 "model at 'Speed' from it (a speed sweep then reduces nothing per speed); "
                 "empty: reduce at 'Speed' directly");
  addInt(rot, "Sample speeds", 2,
         "Speeds of the range reduced directly (Chebyshev-Lobatto points in Omega^2, "
         "both ends included)",
         2, 12);
  addDoubleArray(rot, "Imported speeds", {},
                 "A CalculiX model (Mesh Type CalculiX) at speed: the speeds (rad/s, "
                 "increasing) of the ccx runs of 'Imported jobs', the samples of the "
                 "parametric model over 'Speed range' = {first, last}; empty: none");
  addStringArray(rot, "Imported jobs", {},
                 "One ccx job per 'Imported speeds' (path without extension, relative to "
                 "the deck): its .sti, .mas, .dof from a perturbation step with *FREQUENCY, "
                 "SOLVER=MATRIXSTORAGE after the centrifugal static step, its .dat the static "
                 "displacement of every node (*NODE PRINT U)");
  addEnum(
      rot, "Static state", "Automatic", {"Linear", "Stress-stiffened", "Automatic"}, {0, 1, 2},
      "The centrifugal static state: Linear, (K_e - Omega^2 M_perp) u_s = Omega^2 f_c; Stress-stiffened, "
      "K_sigma(u_s) added to the left side by fixed point (the tension that untwists a blade stiffens it against its "
      "own load: close to a geometrically nonlinear static step); Automatic, the stress-stiffened state where it "
      "moves the largest static displacement by more than 'Static tolerance' of the linear one");
  addDouble(rot, "Static tolerance", 0.01,
            "Automatic static state: the relative change of the largest static "
            "displacement above which the stress-stiffened state is kept",
            0.0, 1.0);
  addBool(rot, "Stress stiffening", true, "Keep the geometric stiffness K_sigma of the centrifugal prestress");
  addBool(rot, "Spin softening", true,
          "Keep -Omega^2 M_perp, the change of the centrifugal load with the "
          "displacement, in the static state and in the stiffness");
  addBool(rot, "Coriolis", false,
          "Keep the Coriolis (gyroscopic) terms Omega G u' in the dynamics, G = 2 int rho N^T [a]_x N, "
          "projected on the reduced basis (Craig-Bampton, Guyan or None; a fixed speed, no 'Speed law' ramp, "
          "a built-in mesh, frictionless contact); false: their size is reported only");
  auto& law = rot.sublist("Speed law", false,
                          "A run-up: the body's speed follows a law in time, its model and "
                          "static state taken from the parametric model at each speed, and the "
                          "turning surfaces follow the same law (docs/user/rotating-bodies.md)");
  addEnum(law, "Type", "Constant", {"Constant", "Ramp"}, {0, 1},
          "Constant: the body turns at 'Speed'; Ramp: from 'Start speed' at 'Start time' to 'End speed' at 'End "
          "time' linearly, constant before and after (needs 'Speed range' holding both speeds, and 'Speed' = "
          "'Start speed')");
  addDouble(law, "Start speed", 0.0, "Ramp: the speed (rad/s) up to 'Start time'");
  addDouble(law, "End speed", 0.0, "Ramp: the speed (rad/s) from 'End time' on");
  addDouble(law, "Start time", 0.0, "Ramp: when the speed starts to change (s)", 0.0);
  addDouble(law, "End time", 0.0, "Ramp: when it reaches 'End speed' (s), after 'Start time'", 0.0);
  addReductionParameters(body);
}

/// Surfaces: one sublist per surface, rigid or carried by a flexible body.
void addSurfaceParameters(Teuchos::ParameterList& pl) {
  auto& surf =
      pl.sublist("Surfaces", false, "One sublist per surface, named by the user")
          .sublist("*", false,
                   "A surface: bicubic B-spline through a grid of points (thesis section 2.4), rigid or carried "
                   "by a flexible body");
  addEnum(
      surf, "Type", "Plane", {"Plane", "Cylinder arc", "Body face", "Casing"},
      {int(SurfaceType::Plane), int(SurfaceType::CylinderArc), int(SurfaceType::BodyFace), int(SurfaceType::Casing)},
      "Plane: a rigid grid of points Origin + i/(nu-1) U + j/(nv-1) V; Cylinder arc: the rigid grid Center + "
      "Radius (cos a e1 + sin a e2) + s Axis over the Angles and the Axial range (e1 = Reference, e2 = Axis x "
      "e1); Body face: the node grid 'Node grid' of the flexible body 'Body', rebuilt from its moved nodes at "
      "every step (its nodes must be retained by the body's reduction; clamped ones stay fixed), the two "
      "bodies corrected together (eq. 2.33). Each grid is interpolated by the general bicubic B-spline code; "
      "a grid whose last row repeats the first is closed. Casing: a closed cone about the z axis (Radius, Cone "
      "angle, Axial position, Axial range, Points {angles, axial}) with a clearance law, facing the axis");
  addDouble(surf, "Cone angle", 0.0, "Casing: half-angle of the cone (degrees)", -60.0, 60.0);
  addDouble(surf, "Axial position", 0.0, "Casing: z where the cone's radius is Radius (m)");
  addClearanceLaw(surf, "Casing", "Radius");
  addString(surf, "Body", "", "Body face: the body that carries the surface");
  addString(surf, "Node grid", "",
            "Body face: the body's ordered face, e.g. x+ (Box) or outer (Ring segment); "
            "its normal points out of the body");
  addDoubleArray(surf, "Origin", {0, 0, 0}, "Plane: corner of the grid (m)");
  addDoubleArray(surf, "U", {0, 1, 0}, "Plane: first edge vector of the grid (m)");
  addDoubleArray(surf, "V", {0, 0, 1}, "Plane: second edge vector of the grid (m)");
  addIntArray(surf, "Points", {5, 5},
              "Grid points along U and V (Plane) or along the arc and the axis "
              "(Cylinder arc); at least 4 each");
  addDoubleArray(surf, "Center", {0, 0, 0}, "Cylinder arc: a point of the axis (m)");
  addDoubleArray(surf, "Axis", {0, 0, 1}, "Cylinder arc: axis direction");
  addDoubleArray(surf, "Reference", {1, 0, 0}, "Cylinder arc: direction of angle 0 (orthogonal to the axis)");
  addDouble(surf, "Radius", 0.18, "Cylinder arc: radius (m)", 1e-300);
  addDoubleArray(surf, "Angles", {-40, 40}, "Cylinder arc: first and last angle of the grid (degrees)");
  addDoubleArray(surf, "Axial range", {-0.05, 0.05}, "Cylinder arc: first and last axial coordinate (m)");
  addDouble(surf, "Rotation speed", 0.0,
            "The surface turns at this speed (rad/s) about 'Rotation axis' through "
            "'Rotation center', in the frame of the contact nodes' bodies (thesis "
            "section 3.3: for a blade spinning at +Omega in its casing, the casing "
            "turns at -Omega about the engine axis). A Body face turns with its body's "
            "frame: the carrying body vibrates in its own frame, only the contact sees "
            "the rotation");
  addDouble(surf, "Initial angle", 0.0,
            "The angle (degrees) the surface is turned by at t = 0, about the rotation "
            "axis");
  addDoubleArray(surf, "Rotation axis", {0, 0, 1}, "Axis of the rotation (need not be unit)");
  addDoubleArray(surf, "Rotation center", {0, 0, 0}, "A point of the rotation axis (m)");
  surf.sublist("Coating", false,
               "Rigid surfaces: an abradable coating in front of the surface (Legrand, Batailly "
               "& Pierre 2012): elastic-plastic bar elements whose plastic shortening is the "
               "wear; no 'Elements': none")
      .setParameters(*CoatingMaterial::getValidParameters());
  addBool(surf, "Flip normal", false,
          "The contact side is where U x V points (Plane), away from the axis "
          "(Cylinder arc, the convex side) or out of the body (Body face); set true "
          "for the other side");
}

/// Contact: the contact treatment, the registered laws' names and each law's own keys.
void addContactParameters(Teuchos::ParameterList& pl) {
  auto& contact = pl.sublist("Contact", false, "Contact treatment (thesis section 2.5)");
  contact.setParameters(*contactValidParameters());  // each law's own keys (Epaphe_ContactLaw.hpp)
}

/// Time: the explicit central difference and its damping.
void addTimeParameters(Teuchos::ParameterList& pl) {
  auto& time = pl.sublist("Time", false, "Explicit central difference (thesis eq. 2.2)");
  addDouble(time, "Time step", 1e-7, "h (s)", 1e-300);
  addDouble(time, "End time", 1e-4, "Simulated duration (s)", 1e-300);
  addDouble(time, "End revolutions", 0.0,
            "When > 0, the duration in revolutions of the fastest turning surface "
            "(replaces End time)",
            0.0);
  addEnum(time, "Initial state", "At rest", {"At rest", "Static equilibrium"}, {0, 1},
          "At rest: q_0 = 0 (the bodies undeformed, moving at their 'Initial velocity'); Static equilibrium: the "
          "static equilibrium under the loads at t = 0 with the contact nodes that touch a surface held by it, "
          "sticking where the friction cone allows (docs/theory/forced-response.md, eqs. 71-72; Lagrange contact, "
          "rigid surfaces at rest)");
  addBool(time, "Allow unstable time step", false,
          "Run even when h exceeds the estimated critical step "
          "(a warning instead of an error)");
  auto& damp = time.sublist("Damping", false, "Damping matrix D");
  addEnum(damp, "Type", "None", {"None", "Rayleigh", "Modal"},
          {int(DampingType::None), int(DampingType::Rayleigh), int(DampingType::Modal)},
          "None; Rayleigh D = alpha M + beta K (eq. 4.3); Modal: the same ratio on every mode of the reduced "
          "model, D = M V diag(2 xi omega) V^T M (eqs. 4.4-4.5)");
  addDouble(damp, "Alpha", 0.0, "Rayleigh mass coefficient (1/s)", 0.0);
  addDouble(damp, "Beta", 0.0, "Rayleigh stiffness coefficient (s)", 0.0);
  addDoubleArray(damp, "Rayleigh frequencies", {},
                 "Rayleigh: {f1, f2} (Hz) where the ratios below are met; when "
                 "given, Alpha and Beta are computed from them (eqs. 4.1-4.2)");
  addDoubleArray(damp, "Rayleigh ratios", {}, "Rayleigh: damping ratios {xi1, xi2} at the two frequencies");
  addDouble(damp, "Ratio", 0.0, "Modal damping ratio xi (0.005 is 0.5 %)", 0.0, 1.0);
}

/// Output: the HDF5 history, field frames and checkpoints.
void addOutputParameters(Teuchos::ParameterList& pl) {
  auto& out = pl.sublist("Output", false, "HDF5 history");
  addString(out, "File", "epaphe.h5", "HDF5 output file (relative paths: from the working directory)");
  addInt(out, "Every", 10, "Steps between two records", 1);
  addInt(out, "Wear every", 0,
         "Steps between two records of an abradable coating's wear map (/coating/<s>/wear; "
         "the last step is always recorded); 0: 100 x Every",
         0);
  addInt(out, "Fields every", 0,
         "Steps between two frames of the full displacement field of every body, "
         "written to /bodies/<b>/fields with an XDMF file <output stem>.xmf that ParaView "
         "opens (0: none)",
         0);
  addBool(out, "Compression", false,
          "Compress the histories (shuffle + deflate): smaller files, but a compressed "
          "chunk completed after a checkpoint is written anew elsewhere or in place with "
          "other bytes, so a process killed during that write can damage records already "
          "flushed; uncompressed (the default), a kill -9 at any time leaves every record of "
          "the last checkpoint readable");
  addInt(out, "Checkpoint every", 0,
         "Steps between two checkpoints (0: none by step count). A checkpoint stores in "
         "the older of /checkpoint/0 and /checkpoint/1, then names it in /checkpoint/current, what the run needs to "
         "continue bit for bit (step, q_{n-1} and q_n, "
         "energy and summary accumulators, the contact's warm starts, the records of every "
         "series) and flushes the file; `epaphe-run DECK --restart FILE` continues from the "
         "last one. Checkpoints are also taken at step 0, every 'Checkpoint interval' "
         "seconds, on SIGINT/SIGTERM, and whenever 1023 records (15 field frames) are "
         "buffered, so that the file is written only at checkpoints and stays readable "
         "after a crash or kill -9 (up to the last checkpoint)",
         0);
  addDouble(out, "Checkpoint interval", 60.0,
            "Wall-clock seconds between two checkpoints (0: none by time); see "
            "'Checkpoint every'",
            0.0);
  addDouble(out, "Energy balance tolerance", 1e-6,
            "The run stops when |energy balance error| / largest energy exceeds it", 0.0);
}

/// Steady state: the detection of a driven run's steady state (Epaphe_SteadyState.hpp, eq. (70)).
void addSteadyStateParameters(Teuchos::ParameterList& pl) {
  auto& ss = pl.sublist("Steady state", false,
                        "Detect the steady state of a driven run (docs/theory/forced-response.md, eq. 70): the "
                        "harmonics of a watched motion over each drive period, steady when the first repeats "
                        "after a few periods; written to /steady_state");
  addBool(ss, "Enabled", false, "Watch for the steady state");
  addString(ss, "Body", "", "The watched body (empty: the deck's only body)");
  addString(ss, "Node set", "", "x is the mean displacement of this node set's nodes along 'Direction' (required)");
  addDoubleArray(ss, "Direction", {1, 0, 0}, "The direction d of the watched motion x = d . u (need not be unit)");
  addDouble(ss, "Frequency", 0.0,
            "The drive's frequency nu (Hz; 0: the first Harmonic load's); a period must be a whole number of steps",
            0.0);
  addDouble(ss, "Tolerance", 1e-6,
            "eps: steady when the first harmonic repeats to eps of itself after p periods, over p + Window periods",
            0.0);
  addInt(ss, "Longest pattern", 10, "P: the longest pattern p looked for (periods)", 1, 1000);
  addInt(ss, "Window", 4, "W: the pattern must hold over the last p + W periods", 1, 1000);
  addInt(ss, "Harmonics", 3, "H: the harmonics a_1 .. a_H written (with the mean a_0)", 1, 100);
  addBool(ss, "Stop", true, "End the run once steady (its status 'complete: steady state ...')");
}

}  // namespace

Teuchos::RCP<const Teuchos::ParameterList> validDeckParameters() {
  // Built again when a program registers a contact law, an observer, a reduction method or an importer:
  // their names and keys are in the schema.
  static std::mutex mutex;
  static Teuchos::RCP<const Teuchos::ParameterList> valid;
  static std::array<int, 4> revision{-1, -1, -1, -1};
  std::lock_guard<std::mutex> lock(mutex);
  const std::array<int, 4> now{contactLawRevision(), observerRevision(), ReductionRegistry::version(),
                               ImporterRegistry::version()};
  if (valid.is_null() || now != revision) {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Epaphe"));
    addRunParameters(*pl);
    addBodyParameters(*pl);
    addSurfaceParameters(*pl);
    addContactParameters(*pl);
    addTimeParameters(*pl);
    addOutputParameters(*pl);
    addSteadyStateParameters(*pl);
    addObserverParameters(*pl);
    valid = pl;
    revision = now;
  }
  return valid;
}

Deck readDeckFromString(const std::string& xml, const std::string& origin) {
  Deck d;
  d.text = xml;
  d.origin = origin;
  d.params = readXmlString(xml, origin);
  d.params->setName("Epaphe");
  validateAndSetDefaults(*d.params, *validDeckParameters(), origin, xml);
  return d;
}

std::string stem(const std::string& path) {
  const auto dot = path.rfind('.');
  const auto slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path;
  return path.substr(0, dot);
}

std::string cacheFileOf(const Teuchos::ParameterList& rp, const std::string& outputPath, const std::string& body) {
  const std::string given = rp.get<std::string>("Cache file");
  return given.empty() ? stem(outputPath) + "." + body + ".rom.h5" : given;
}

Deck deckAtSpeed(const Deck& deck, double omega, double revolutions, const std::string& outputFile) {
  EPAPHE_REQUIRE(std::isfinite(omega) && omega > 0,
                 deck.origin << ": rotation speed " << omega << " rad/s for a speed sweep; give speeds > 0");
  auto raw = readXmlString(deck.text, deck.origin);
  int turning = 0;
  if (raw->isSublist("Surfaces")) {
    Teuchos::ParameterList& surfs = raw->sublist("Surfaces");
    for (auto it = surfs.begin(); it != surfs.end(); ++it) {
      if (!surfs.isSublist(surfs.name(it))) continue;
      Teuchos::ParameterList& s = surfs.sublist(surfs.name(it));
      if (s.isType<double>("Rotation speed") && s.get<double>("Rotation speed") != 0.0) {
        s.set("Rotation speed", std::copysign(omega, s.get<double>("Rotation speed")));
        ++turning;
      }
    }
  }
  EPAPHE_REQUIRE(turning > 0, deck.origin << ": no surface turns (no non-zero 'Surfaces-><name>->Rotation speed'), "
                                             "so a speed sweep has nothing to vary");
  // A rotating body turns at the sweep's speed too (its sense kept): its model at that speed comes
  // from its parametric model when it has a 'Speed range' (nothing reduced per speed).
  if (raw->isSublist("Bodies")) {
    Teuchos::ParameterList& bodies = raw->sublist("Bodies");
    for (auto it = bodies.begin(); it != bodies.end(); ++it) {
      if (!bodies.isSublist(bodies.name(it)) || !bodies.sublist(bodies.name(it)).isSublist("Rotation")) continue;
      Teuchos::ParameterList& rot = bodies.sublist(bodies.name(it)).sublist("Rotation");
      const double speed = rot.isType<double>("Speed") ? rot.get<double>("Speed") : 0.0;
      if (speed != 0.0 || rot.isParameter("Speed range"))
        rot.set("Speed", std::copysign(omega, speed == 0.0 ? 1.0 : speed));
      // every speed reads the one parametric model: its cache is named after the deck's own output,
      // not after each speed's
      Teuchos::ParameterList& red = bodies.sublist(bodies.name(it)).sublist("Reduction");
      const bool named = red.isType<std::string>("Cache file") && !red.get<std::string>("Cache file").empty();
      if (rot.isParameter("Speed range") && !named) {
        const Teuchos::ParameterList& P = *deck.params;
        red.set("Cache file", cacheFileOf(P.sublist("Bodies").sublist(bodies.name(it)).sublist("Reduction"),
                                          P.sublist("Output").get<std::string>("File"), bodies.name(it)));
      }
    }
  }
  if (revolutions > 0) {
    Teuchos::ParameterList& time = raw->sublist("Time");
    time.remove("End time", false);
    time.set("End revolutions", revolutions);
  }
  raw->sublist("Output").set("File", outputFile);
  std::ostringstream xml;
  Teuchos::writeParameterListToXmlOStream(*raw, xml);
  return readDeckFromString(xml.str(), deck.origin);
}

Deck readDeck(const std::string& path) {
  std::error_code ec;
  EPAPHE_REQUIRE(!std::filesystem::is_directory(path, ec), "deck '" << path << "' is a directory; give an XML file");
  std::ifstream in(path);
  EPAPHE_REQUIRE(in, "deck '" << path << "' cannot be opened: check the path and its permissions");
  std::stringstream ss;
  ss << in.rdbuf();
  EPAPHE_REQUIRE(!in.bad(), "deck '" << path << "' cannot be read: check the file");
  EPAPHE_REQUIRE(ss.str().find_first_not_of(" \t\r\n") != std::string::npos,
                 "deck '" << path << "' is empty; a deck is <ParameterList name=\"Epaphe\"> ... </ParameterList>");
  return readDeckFromString(ss.str(), path);
}

}  // namespace epaphe
