"""Physics engines on the paper's slope and belt, against stickslip's exact methods.

Runs each installed engine through its own Python package (``pip install .[engines]`` for
MuJoCo and pybullet, ``.[drake]`` for Drake, ``pip install newton warp-lang`` for Newton on the
CPU): the slope box (10 kg, a 0.2 x 0.2 x 0.1 m box on a 10-degree slope; the slope is the
gravity vector tilted by theta over a level plane; mu = mu_k = 0.30 for the engines with one
coefficient, mu_s = 0.35 and mu_d = 0.30 for Drake) at the engines' defaults and along their
friction settings and time steps, and the mass on a belt moving at BELT_SPEED; beside each
measured creep the creep that stickslip.engine_creep predicts from the engine's law, and
event_driven and moreau (which hold the box exactly) with the CPU time per simulated second of
each::

    python -m cases.engines --outdir out/

Writes engines_slope.csv (one row per run: measured and predicted creep, CPU time),
engines_belt.csv (amplitude, period, stuck time per period and the friction coefficient at the
first release of each run, exact ones first), engines_belt_series.csv (the velocities),
engines_versions.csv (the version of every engine used), Markdown tables of the first two, and
the figures engines_slope_creep.png and engines_belt.png. --replot redraws from the CSVs.

An engine that is not installed is skipped, with a line saying how to install it. Written to a
directory whose engines_versions.csv records an engine that is not installed here (the
committed docs/figures, made with Drake and Newton), the driver leaves that directory's results
as they are and says so, unless --force: so ``python -m cases --all --docs`` on a machine
without every engine does not drop their rows.
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c

T_END: float = 20.0            # [s], the paper's slope run
BELT_T_END: float = 10.0       # [s]
#: The belt's speed [m/s]: slow enough for the paper's law to stick-slip (at the paper's
#: 1.5 m/s the mass started at rest never reaches the belt's speed: it only slips)
BELT_SPEED: float = 0.1
#: |v - v_b| below which the mass counts as stuck [m/s]
STICK_TOL: float = 1e-4
BELT_MASS: float = 1e8          # [kg], Drake's belt body
THETA_DEG: float = 10.0
MASS: float = 10.0
G: float = 9.81
MU: float = 0.30               # the one coefficient of MuJoCo and Bullet: mu_k
HALF: tuple[float, float, float] = (0.1, 0.1, 0.05)     # box half-sizes [m]: aspect 0.5


def versions() -> dict[str, str]:
    """The installed engines and their versions (absent ones are left out)."""
    out: dict[str, str] = {}
    try:
        import mujoco
        out["mujoco"] = mujoco.__version__
    except ImportError:
        pass
    import importlib.metadata as md
    for name, module, dist in (("bullet", "pybullet", "pybullet"), ("drake", "pydrake", "drake"),
                               ("newton", "newton", "newton"), ("warp", "warp", "warp-lang")):
        try:
            __import__(module)
            out[name] = md.version(dist)
        except Exception:
            pass
    return out


def _gravity(theta_deg: float) -> tuple[float, float, float]:
    th = math.radians(theta_deg)
    return (G * math.sin(th), 0.0, -G * math.cos(th))


def _creep_of(t: np.ndarray, x: np.ndarray) -> float:
    """Mean speed over the second half of a run [m/s]."""
    half = len(t) // 2
    return float((x[-1] - x[half]) / (t[-1] - t[half]))


# ------------------------------------------------------------------------------------------
# MuJoCo
# ------------------------------------------------------------------------------------------
def _mujoco_belt_xml(*, timestep: float, cone: str, impratio: float) -> str:
    """MuJoCo's model of the mass on the belt: the box on a slide joint with a spring to the
    wall (k = 300 N/m) and free to move vertically, on a 1000 kg belt body on its own slide."""
    fr = f'friction="{MU} 0.005 0.0001"'
    k = 300.0
    g = _gravity(0.0)
    world = (f'<body name="belt" pos="0 0 -0.05"><joint name="belt" type="slide" axis="1 0 0"/>'
             f'<geom type="box" size="100 1 0.05" mass="1000" {fr}/></body>'
             f'<body name="mass" pos="0 0 {HALF[2]}">'
             f'<joint name="x" type="slide" axis="1 0 0" stiffness="{k}"/>'
             f'<joint name="z" type="slide" axis="0 0 1"/>'
             f'<geom type="box" size="{HALF[0]} {HALF[1]} {HALF[2]}" mass="{MASS}" {fr}/>'
             f'</body>')
    return (f'<mujoco><option timestep="{timestep}" cone="{cone}" impratio="{impratio}" '
            f'gravity="{g[0]} {g[1]} {g[2]}"/>'
            f'<worldbody>{world}</worldbody></mujoco>')


def mujoco_slope(*, timestep: float = 0.002, cone: str = "pyramidal", impratio: float = 1.0,
                 t_end: float = T_END, theta_deg: float = THETA_DEG,
                 solref: Sequence[float] | None = None) -> dict[str, Any]:
    """The slope box in MuJoCo (its model: `stickslip.engines.mujoco_slope_xml`): creep speed
    [m/s], contacts (the fewest active at any sampled step), CPU time per simulated second."""
    import mujoco
    import stickslip.engines as en
    m = mujoco.MjModel.from_xml_string(en.mujoco_slope_xml(
        timestep=timestep, cone=cone, impratio=impratio, theta_deg=theta_deg, mu=MU, m=MASS,
        g=G, aspect=HALF[2] / HALF[0], **({} if solref is None else {"solref": solref})))
    d = mujoco.MjData(m)
    n = int(round(t_end / timestep))
    every = max(1, n // 2000)
    t, x = [0.0], [0.0]
    fewest = 1 << 30
    cpu = time.process_time()
    for i in range(1, n + 1):
        mujoco.mj_step(m, d)
        if i % every == 0:
            t.append(d.time)
            x.append(float(d.qpos[0]))
            fewest = min(fewest, int(d.ncon))
    cpu = time.process_time() - cpu
    return {"creep": _creep_of(np.array(t), np.array(x)), "x_end": x[-1], "n_contacts": int(d.ncon),
            "fewest_contacts": fewest, "cpu_per_s": cpu / t_end}


#: The settings over which ``--rocking`` measures MuJoCo's rocking threshold: (cone, timestep
#: [s], solref timeconst [s], impratio).
ROCKING_GRID: tuple[tuple[str, float, float, float], ...] = tuple(
    [("pyramidal", 0.002, 0.02, ir) for ir in (1.0, 3.0, 10.0, 30.0, 100.0)]
    + [(cone, h, tc, 1.0) for cone in ("pyramidal", "elliptic")
       for h, tc in ((0.0005, 0.02), (0.001, 0.02), (0.005, 0.02), (0.002, 0.05), (0.002, 0.1),
                     (0.001, 0.01))]
    + [("elliptic", 0.002, 0.02, ir) for ir in (1.0, 10.0, 100.0)])


def mujoco_rocking_threshold(cone: str, timestep: float, timeconst: float, impratio: float,
                             t_end: float = 10.0, rounds: int = 7) -> tuple[float, float]:
    """The damping ratio (solref's second number) below which the slope box rocks in MuJoCo:
    by bisection on [0.2, 1], a run "holds" when all four contacts stay active and its creep is
    within 1 % of `stickslip.engine_creep`'s. Returns (rocks at, holds at)."""
    import warnings
    import stickslip as ss
    lo, hi = 0.2, 1.0
    for _ in range(rounds):
        mid = 0.5 * (lo + hi)
        out = mujoco_slope(timestep=timestep, cone=cone, impratio=impratio, t_end=t_end,
                           solref=(timeconst, mid))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ss.engines.EngineDomainWarning)
            pred = ss.engine_creep("mujoco", cone=cone, impratio=impratio, timestep=timestep,
                                   solref=(timeconst, mid), mu=MU, aspect=HALF[2] / HALF[0])
        holds = out["fewest_contacts"] == 4 and abs(out["creep"] / pred - 1) < 0.01
        lo, hi = (lo, mid) if holds else (mid, hi)
    return lo, hi


def rocking(outdir: Path, quiet: bool = False) -> list[Path]:
    """MuJoCo's rocking threshold over `ROCKING_GRID` (engines_rocking.csv), the measurement
    behind `stickslip.engines.ROCKING_DAMPRATIO`."""
    rows = []
    for cone, h, tc, ir in ROCKING_GRID:
        lo, hi = mujoco_rocking_threshold(cone, h, tc, ir)
        c.log(f"  mujoco {cone:9s} timestep {h:g} s, timeconst {tc:g} s, impratio {ir:g}: "
              f"rocks at dampratio {lo:.4g}, holds at {hi:.4g}", quiet)
        rows.append([cone, h, tc, ir, lo, hi])
    return [c.write_csv(Path(outdir) / "engines_rocking.csv",
                        ["cone [-]", "timestep [s]", "timeconst [s]", "impratio [-]",
                         "rocks_at_dampratio [-]", "holds_at_dampratio [-]"], rows)]


def mujoco_belt(*, timestep: float = 0.002, cone: str = "pyramidal", impratio: float = 1.0,
                t_end: float = BELT_T_END, v_b: float = BELT_SPEED) -> dict[str, np.ndarray]:
    """The mass on the belt in MuJoCo (the belt's velocity held at v_b every step): t, x, v."""
    import mujoco
    m = mujoco.MjModel.from_xml_string(_mujoco_belt_xml(timestep=timestep, cone=cone,
                                                        impratio=impratio))
    d = mujoco.MjData(m)
    jb = m.joint("belt").dofadr[0]
    jx = m.joint("x").qposadr[0]
    n = int(round(t_end / timestep))
    t, x, v = np.zeros(n + 1), np.zeros(n + 1), np.zeros(n + 1)
    cpu = time.process_time()
    for i in range(1, n + 1):
        d.qvel[jb] = v_b
        mujoco.mj_step(m, d)
        t[i], x[i], v[i] = d.time, d.qpos[jx], d.qvel[m.joint("x").dofadr[0]]
    cpu = time.process_time() - cpu
    return {"t": t, "x": x, "v": v, "cpu_per_s": cpu / t_end}


# ------------------------------------------------------------------------------------------
# Bullet
# ------------------------------------------------------------------------------------------
def bullet_slope(*, timestep: float = 1 / 240, t_end: float = T_END,
                 theta_deg: float = THETA_DEG) -> dict[str, Any]:
    """The slope box in Bullet (pybullet, DIRECT): creep speed [m/s], CPU time per simulated
    second. Bullet multiplies the two bodies' friction coefficients: the plane gets 1, the box
    mu."""
    import pybullet as p
    cid = p.connect(p.DIRECT)
    try:
        p.setGravity(*_gravity(theta_deg), physicsClientId=cid)
        p.setTimeStep(timestep, physicsClientId=cid)
        plane = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=cid),
                                  physicsClientId=cid)
        box = p.createMultiBody(MASS, p.createCollisionShape(p.GEOM_BOX, halfExtents=HALF,
                                                             physicsClientId=cid),
                                basePosition=(0, 0, HALF[2]), physicsClientId=cid)
        p.changeDynamics(plane, -1, lateralFriction=1.0, physicsClientId=cid)
        p.changeDynamics(box, -1, lateralFriction=MU, physicsClientId=cid)
        n = int(round(t_end / timestep))
        every = max(1, n // 2000)
        t, x = [0.0], [0.0]
        cpu = time.process_time()
        for i in range(1, n + 1):
            p.stepSimulation(physicsClientId=cid)
            if i % every == 0:
                t.append(i * timestep)
                x.append(p.getBasePositionAndOrientation(box, physicsClientId=cid)[0][0])
        cpu = time.process_time() - cpu
        ncon = len(p.getContactPoints(box, plane, physicsClientId=cid))
    finally:
        p.disconnect(cid)
    return {"creep": _creep_of(np.array(t), np.array(x)), "x_end": x[-1], "n_contacts": ncon,
            "cpu_per_s": cpu / t_end}


def bullet_belt(*, timestep: float = 1 / 240, t_end: float = BELT_T_END,
                v_b: float = BELT_SPEED) -> dict[str, np.ndarray]:
    """The mass on the belt in Bullet: the belt a link on a prismatic joint driven at v_b by a
    velocity motor, the spring -k x applied to the mass every step. Returns t, x, v."""
    import pybullet as p
    k = 300.0
    cid = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, -G, physicsClientId=cid)
        p.setTimeStep(timestep, physicsClientId=cid)
        belt_shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=(100, 1, 0.05),
                                            physicsClientId=cid)
        belt = p.createMultiBody(0, -1, basePosition=(0, 0, -0.05), linkMasses=[1000.0],
                                 linkCollisionShapeIndices=[belt_shape],
                                 linkVisualShapeIndices=[-1],
                                 linkPositions=[(0, 0, 0)], linkOrientations=[(0, 0, 0, 1)],
                                 linkInertialFramePositions=[(0, 0, 0)],
                                 linkInertialFrameOrientations=[(0, 0, 0, 1)],
                                 linkParentIndices=[0], linkJointTypes=[p.JOINT_PRISMATIC],
                                 linkJointAxis=[(1, 0, 0)], physicsClientId=cid)
        box = p.createMultiBody(MASS, p.createCollisionShape(p.GEOM_BOX, halfExtents=HALF,
                                                             physicsClientId=cid),
                                basePosition=(0, 0, HALF[2]), physicsClientId=cid)
        p.changeDynamics(belt, 0, lateralFriction=1.0, physicsClientId=cid)
        p.changeDynamics(box, -1, lateralFriction=MU, physicsClientId=cid)
        p.setJointMotorControl2(belt, 0, p.VELOCITY_CONTROL, targetVelocity=v_b, force=1e7,
                                physicsClientId=cid)
        n = int(round(t_end / timestep))
        t, x, v = np.zeros(n + 1), np.zeros(n + 1), np.zeros(n + 1)
        cpu = time.process_time()
        for i in range(1, n + 1):
            pos = p.getBasePositionAndOrientation(box, physicsClientId=cid)[0]
            p.applyExternalForce(box, -1, (-k * pos[0], 0, 0), pos, p.WORLD_FRAME,
                                 physicsClientId=cid)
            p.stepSimulation(physicsClientId=cid)
            t[i] = i * timestep
            x[i] = p.getBasePositionAndOrientation(box, physicsClientId=cid)[0][0]
            v[i] = p.getBaseVelocity(box, physicsClientId=cid)[0][0]
        cpu = time.process_time() - cpu
    finally:
        p.disconnect(cid)
    return {"t": t, "x": x, "v": v, "cpu_per_s": cpu / t_end}


# ------------------------------------------------------------------------------------------
# Drake
# ------------------------------------------------------------------------------------------
DRAKE_MODES: tuple[str, ...] = ("continuous", "tamsi", "sap", "lagged")


def _drake_plant(mode: str, timestep: float):
    """A Drake diagram builder and plant in `mode` ("continuous", or a discrete approximation:
    "tamsi", "sap", "lagged") with point contact, and the paper's friction (0.35, 0.30)."""
    from pydrake.all import (AddMultibodyPlantSceneGraph, ContactModel, CoulombFriction,
                             DiagramBuilder, DiscreteContactApproximation)
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=0.0 if mode == "continuous"
                                           else timestep)
    if mode != "continuous":
        plant.set_discrete_contact_approximation(
            {"tamsi": DiscreteContactApproximation.kTamsi, "sap": DiscreteContactApproximation.kSap,
             "lagged": DiscreteContactApproximation.kLagged}[mode])
    plant.set_contact_model(ContactModel.kPoint)
    return builder, plant, CoulombFriction(0.35, 0.30)


def drake_slope(*, mode: str = "lagged", stiction_tolerance: float = 1e-4, timestep: float = 1e-3,
                t_end: float = T_END, theta_deg: float = THETA_DEG) -> dict[str, Any]:
    """The slope box in Drake's MultibodyPlant with point contact (mu_s = 0.35, mu_d = 0.30):
    the box's collision geometry is four spheres of radius 1 mm at its bottom corners (four
    contacts, as MuJoCo's box). mode "continuous" (time_step 0, Drake's default integrator,
    RK3 with error control) or a discrete contact approximation ("tamsi", "sap", "lagged",
    Drake's default) at timestep. Returns creep speed [m/s] and CPU time per simulated second."""
    from pydrake.all import HalfSpace, RigidTransform, Simulator, SpatialInertia, Sphere
    builder, plant, friction = _drake_plant(mode, timestep)
    plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform(), HalfSpace(), "ground",
                                    friction)
    box = plant.AddRigidBody("box", SpatialInertia.SolidBoxWithMass(MASS, *(2 * h for h in HALF)))
    for i, (x, y) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)]):
        plant.RegisterCollisionGeometry(box, RigidTransform([x * HALF[0], y * HALF[1], -HALF[2]]),
                                        Sphere(1e-3), f"corner{i}", friction)
    plant.mutable_gravity_field().set_gravity_vector(_gravity(theta_deg))
    plant.set_stiction_tolerance(stiction_tolerance)
    plant.Finalize()
    sim = Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(sim.get_mutable_context())
    plant.SetFreeBodyPose(context, box, RigidTransform([0, 0, HALF[2] + 1e-3]))
    sim.Initialize()
    t = np.linspace(0.0, t_end, 401)
    x = np.zeros_like(t)
    cpu = time.process_time()
    for i in range(1, len(t)):
        sim.AdvanceTo(t[i])
        x[i] = plant.EvalBodyPoseInWorld(context, box).translation()[0]
    cpu = time.process_time() - cpu
    return {"creep": _creep_of(t, x), "x_end": float(x[-1]), "n_contacts": 4,
            "cpu_per_s": cpu / t_end}


def drake_belt(*, mode: str = "lagged", stiction_tolerance: float = 1e-4, timestep: float = 1e-3,
               t_end: float = BELT_T_END, v_b: float = BELT_SPEED) -> dict[str, np.ndarray]:
    """The mass on the belt in Drake (point contact, mu_s = 0.35, mu_d = 0.30; four corner
    spheres as on the slope): the mass slides along x on a prismatic joint with a
    PrismaticSpring k and rises and falls on a second one; the belt is a 1e8 kg body on a
    prismatic joint started at v_b (its speed changes by less than 1e-5 m/s in a run). Returns
    t, x, v sampled every millisecond."""
    from pydrake.all import (Box, PrismaticJoint, PrismaticSpring, RigidTransform, Simulator,
                             SpatialInertia, Sphere)
    builder, plant, friction = _drake_plant(mode, timestep)
    belt = plant.AddRigidBody("belt", SpatialInertia.SolidBoxWithMass(BELT_MASS, 200.0, 2.0, 0.1))
    plant.RegisterCollisionGeometry(belt, RigidTransform([0, 0, -0.05]), Box(200.0, 2.0, 0.1),
                                    "belt", friction)
    jb = plant.AddJoint(PrismaticJoint("belt", plant.world_frame(), belt.body_frame(), [1, 0, 0]))
    carriage = plant.AddRigidBody("carriage", SpatialInertia.SolidSphereWithMass(1e-6, 0.01))
    box = plant.AddRigidBody("mass", SpatialInertia.SolidBoxWithMass(MASS, *(2 * h for h in HALF)))
    jx = plant.AddJoint(PrismaticJoint("x", plant.world_frame(), carriage.body_frame(), [1, 0, 0]))
    jz = plant.AddJoint(PrismaticJoint("z", carriage.body_frame(), box.body_frame(), [0, 0, 1]))
    plant.AddForceElement(PrismaticSpring(jx, 0.0, 300.0))
    for i, (x, y) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)]):
        plant.RegisterCollisionGeometry(box, RigidTransform([x * HALF[0], y * HALF[1], -HALF[2]]),
                                        Sphere(1e-3), f"corner{i}", friction)
    plant.set_stiction_tolerance(stiction_tolerance)
    plant.Finalize()
    sim = Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(sim.get_mutable_context())
    jz.set_translation(context, HALF[2] + 1e-3)
    jb.set_translation_rate(context, v_b)
    sim.Initialize()
    t = np.linspace(0.0, t_end, int(round(t_end / 1e-3)) + 1)
    x, v = np.zeros_like(t), np.zeros_like(t)
    cpu = time.process_time()
    for i in range(1, len(t)):
        sim.AdvanceTo(t[i])
        x[i], v[i] = jx.get_translation(context), jx.get_translation_rate(context)
    cpu = time.process_time() - cpu
    return {"t": t, "x": x, "v": v, "cpu_per_s": cpu / t_end,
            "belt_speed_end": float(jb.get_translation_rate(context))}


# ------------------------------------------------------------------------------------------
# Newton (semi-implicit Euler, on the CPU through warp)
# ------------------------------------------------------------------------------------------
#: Newton's run [s]: its CPU path launches warp kernels every step (about 5 s of CPU per
#: simulated second at 1 ms), and its creep is steady after m / (n k_f) = 2.5 ms
NEWTON_T_END: float = 2.0


def newton_slope(*, timestep: float = 1e-3, k_f: float = 1000.0, t_end: float = NEWTON_T_END,
                 theta_deg: float = THETA_DEG) -> dict[str, Any]:
    """The slope box in Newton with SolverSemiImplicit on the CPU (ShapeConfig defaults but
    mu = MU and the given k_f; the box's density gives 10 kg). Returns creep speed [m/s],
    contacts and CPU time per simulated second (kernel compilation excluded)."""
    import warp as wp
    wp.config.quiet = True
    import newton
    builder = newton.ModelBuilder()
    builder.add_ground_plane(cfg=newton.ModelBuilder.ShapeConfig(kf=k_f, mu=MU))
    body = builder.add_body(xform=wp.transform(p=wp.vec3(0.0, 0.0, HALF[2]), q=wp.quat_identity()))
    volume = 8 * HALF[0] * HALF[1] * HALF[2]
    builder.add_shape_box(body, hx=HALF[0], hy=HALF[1], hz=HALF[2],
                          cfg=newton.ModelBuilder.ShapeConfig(kf=k_f, mu=MU, density=MASS / volume))
    model = builder.finalize(device="cpu")
    model.set_gravity(_gravity(theta_deg))
    solver = newton.solvers.SolverSemiImplicit(model)
    s0, s1, control = model.state(), model.state(), model.control()
    pipeline = newton.CollisionPipeline(model)
    contacts = pipeline.contacts()

    def step(s0: Any, s1: Any) -> tuple[Any, Any]:
        s0.clear_forces()
        pipeline.collide(s0, contacts)
        solver.step(s0, s1, control, contacts, timestep)
        return s1, s0

    s0, s1 = step(s0, s1)                      # compiles the kernels (cached by warp)
    n = int(round(t_end / timestep))
    every = max(1, n // 400)
    t, x = [timestep], [float(s0.body_q.numpy()[0][0])]
    cpu = time.process_time()
    for i in range(2, n + 1):
        s0, s1 = step(s0, s1)
        if i % every == 0:
            t.append(i * timestep)
            x.append(float(s0.body_q.numpy()[0][0]))
    cpu = time.process_time() - cpu
    return {"creep": _creep_of(np.array(t), np.array(x)), "x_end": x[-1],
            "n_contacts": int(contacts.rigid_contact_count.numpy()[0]),
            "cpu_per_s": cpu / (t_end - timestep)}


def newton_belt(*, timestep: float = 1e-3, k_f: float = 1000.0, t_end: float = BELT_T_END,
                v_b: float = BELT_SPEED, k: float = 300.0) -> dict[str, np.ndarray]:
    """The mass on the belt in Newton with SolverSemiImplicit on the CPU: the belt a kinematic
    box whose velocity is held at v_b (Newton leaves a kinematic body's state as it is set),
    the box on it with mu = MU and k_f, the spring -k x applied as an external force every
    step. Returns t, x, v and the CPU time per simulated second (kernel compilation
    excluded)."""
    import warp as wp
    wp.config.quiet = True
    import newton
    cfg = newton.ModelBuilder.ShapeConfig
    builder = newton.ModelBuilder()
    belt = builder.add_body(xform=wp.transform(p=wp.vec3(0.0, 0.0, -0.05), q=wp.quat_identity()),
                            is_kinematic=True)
    builder.add_shape_box(belt, hx=100.0, hy=1.0, hz=0.05, cfg=cfg(kf=k_f, mu=MU))
    box = builder.add_body(xform=wp.transform(p=wp.vec3(0.0, 0.0, HALF[2]), q=wp.quat_identity()))
    volume = 8 * HALF[0] * HALF[1] * HALF[2]
    builder.add_shape_box(box, hx=HALF[0], hy=HALF[1], hz=HALF[2],
                          cfg=cfg(kf=k_f, mu=MU, density=MASS / volume))
    model = builder.finalize(device="cpu")
    model.set_gravity((0.0, 0.0, -G))
    solver = newton.solvers.SolverSemiImplicit(model)
    s0, s1, control = model.state(), model.state(), model.control()
    for s in (s0, s1):
        qd = s.body_qd.numpy()
        qd[belt] = (v_b, 0.0, 0.0, 0.0, 0.0, 0.0)
        s.body_qd.assign(qd)
    pipeline = newton.CollisionPipeline(model)
    contacts = pipeline.contacts()
    force = np.zeros((model.body_count, 6))

    def step(s0: Any, s1: Any) -> tuple[Any, Any]:
        s0.clear_forces()
        force[box, 0] = -k * float(s0.body_q.numpy()[box][0])
        s0.body_f.assign(force)
        pipeline.collide(s0, contacts)
        solver.step(s0, s1, control, contacts, timestep)
        return s1, s0

    n = int(round(t_end / timestep))
    t, x, v = np.zeros(n + 1), np.zeros(n + 1), np.zeros(n + 1)
    s0, s1 = step(s0, s1)                      # compiles the kernels (cached by warp)
    t[1], x[1], v[1] = timestep, s0.body_q.numpy()[box][0], s0.body_qd.numpy()[box][0]
    cpu = time.process_time()
    for i in range(2, n + 1):
        s0, s1 = step(s0, s1)
        t[i], x[i], v[i] = i * timestep, s0.body_q.numpy()[box][0], s0.body_qd.numpy()[box][0]
    cpu = time.process_time() - cpu
    return {"t": t, "x": x, "v": v, "cpu_per_s": cpu / (t_end - timestep)}


# ------------------------------------------------------------------------------------------
# stickslip's exact methods
# ------------------------------------------------------------------------------------------
def exact_slope(method: str, t_end: float = T_END) -> dict[str, Any]:
    """The slope under set-valued Coulomb friction (event_driven, moreau at h = 1e-3 s)."""
    import stickslip as ss
    kw = {"h": 1e-3} if method == "moreau" else {}
    res = ss.simulate("slope", "coulomb", method=method, t_end=t_end, **kw)
    return {"creep": _creep_of(res.t, res.x), "x_end": float(res.x[-1]),
            "cpu_per_s": res.stats["cpu_seconds"] / t_end}


def exact_belt(method: str, t_end: float = BELT_T_END, mu_s: float = 0.35,
               mu_k: float = 0.30) -> dict[str, np.ndarray]:
    """The belt (v_b = BELT_SPEED) under set-valued Coulomb friction, from rest."""
    import stickslip as ss
    kw = {"h": 1e-3} if method == "moreau" else {}
    res = ss.simulate("belt", "coulomb", method=method, t_end=t_end, n_out=int(t_end / 1e-3) + 1,
                      v0=0.0, v_b=BELT_SPEED, mu_s=mu_s, mu_k=mu_k, **kw)
    return {"t": res.t, "x": res.x, "v": res.v, "cpu_per_s": res.stats["cpu_seconds"] / t_end}


def first_release(t: np.ndarray, x: np.ndarray, v: np.ndarray, v_b: float = BELT_SPEED,
                  k: float = 300.0) -> float:
    """The friction coefficient at which the first stick ends: k x / (m g) when the mass,
    having reached the belt's speed (within 1 mm/s), first falls 1 mm/s below it again (the
    exact value is mu_s)."""
    near = np.flatnonzero(np.abs(v - v_b) < 1e-3)
    if not len(near):
        return math.nan
    after = np.flatnonzero(v[near[0]:] < v_b - 1e-3)
    if not len(after):
        return math.nan
    return float(k * x[near[0] + after[0]] / (MASS * G))


def stick_summary(t: np.ndarray, x: np.ndarray, v: np.ndarray, v_b: float = BELT_SPEED,
                  tol: float = STICK_TOL) -> dict[str, float]:
    """Amplitude [m] (half the range of x over the second half of the run), period [s] (mean
    time between the upward crossings of the mean of x there) and stick time per period [s]
    (time with |v - v_b| < tol [m/s], over the number of periods)."""
    half = t >= t[-1] / 2
    th, xh, vh = t[half], x[half], v[half]
    amp = 0.5 * float(xh.max() - xh.min())
    mean = 0.5 * float(xh.max() + xh.min())
    up = np.flatnonzero((xh[:-1] < mean) & (xh[1:] >= mean))
    if len(up) < 2 or amp < 1e-6:
        return {"amplitude": amp, "period": math.nan, "stick_per_period": math.nan,
                "stick_fraction": float(np.mean(np.abs(vh - v_b) < tol))}
    period = float(np.mean(np.diff(th[up])))
    dt = np.diff(th)
    stuck = float(np.sum(dt[np.abs(vh[:-1] - v_b) < tol]))
    return {"amplitude": amp, "period": period,
            "stick_per_period": stuck / ((th[-1] - th[0]) / period),
            "stick_fraction": stuck / float(th[-1] - th[0])}


# ------------------------------------------------------------------------------------------
# The study
# ------------------------------------------------------------------------------------------
#: How to install each engine the driver can run (engines_versions.csv's names).
INSTALL: dict[str, str] = {"mujoco": "pip install .[engines]", "bullet": "pip install .[engines]",
                           "drake": "pip install .[drake]",
                           "newton": "pip install newton warp-lang (CPU kernels compile for "
                                     "minutes on first use)"}


def absent_engines() -> list[str]:
    """The engines the driver can run that are not installed here."""
    have = versions()
    return [name for name in INSTALL if name not in have]


def run(outdir: str | Path, *, t_end: float = T_END, belt_t_end: float = BELT_T_END,
        quick: bool = False, quiet: bool = False) -> list[Path]:
    """Run every installed engine and the exact methods; write CSVs and Markdown."""
    import stickslip as ss
    outdir = Path(outdir)
    have = versions()
    for name in absent_engines():
        c.log(f"cases.engines: {name} is not installed ({INSTALL[name]}): skipped", quiet)
    rows: list[list[Any]] = []
    aspect = HALF[2] / HALF[0]

    def add(engine: str, setting: str, cone: str, timestep: float | None, value: float | None,
            out: dict[str, Any], predicted: float | None) -> None:
        pred = "" if predicted is None else f"{predicted * t_end * 1e3:.4g} mm"
        c.log(f"  {engine:16s} {setting:34s} creep {out['creep'] * t_end * 1e3:10.4g} mm "
              f"(predicted {pred or 'none'}), {out['cpu_per_s'] * 1e3:.3g} ms CPU per s", quiet)
        rows.append([engine, setting, cone, timestep, value, out.get("n_contacts"),
                     out["creep"], predicted, out["creep"] * t_end,
                     None if predicted is None else predicted * t_end, out["cpu_per_s"]])

    for method in ("event_driven", "moreau"):
        add(method, "coulomb" + (", h=0.001 s" if method == "moreau" else ""), "",
            1e-3 if method == "moreau" else None, None, exact_slope(method, t_end), 0.0)
    if "mujoco" in have:
        steps = (0.002,) if quick else (0.0005, 0.001, 0.002, 0.005)
        ratios = (1.0, 10.0) if quick else (1.0, 3.0, 10.0, 30.0, 100.0)
        for cone in ("pyramidal", "elliptic"):
            for h in steps:
                for ir in (ratios if h == 0.002 else (1.0,)):
                    out = mujoco_slope(timestep=h, cone=cone, impratio=ir, t_end=t_end)
                    pred = ss.engine_creep("mujoco", cone=cone, impratio=ir, timestep=h,
                                           n_contacts=out["n_contacts"], mu=MU, aspect=aspect)
                    label = ("defaults" if (h == 0.002 and ir == 1.0 and cone == "pyramidal")
                             else f"h={h:g} s, impratio={ir:g}")
                    add("mujoco", label, cone, h, ir, out, pred)
    if "drake" in have:
        runs = ([("lagged", 1e-4, 1e-3), ("tamsi", 1e-4, 1e-3), ("continuous", 1e-2, None)]
                if quick else
                [("lagged", 1e-4, 1e-3), ("lagged", 1e-4, 1e-2), ("lagged", 1e-3, 1e-3),
                 ("sap", 1e-4, 1e-3),
                 ("sap", 1e-4, 1e-2), ("tamsi", 1e-4, 1e-3), ("tamsi", 1e-3, 1e-3),
                 ("tamsi", 1e-2, 1e-3), ("tamsi", 1e-4, 1e-2), ("continuous", 1e-2, None),
                 ("continuous", 1e-3, None), ("continuous", 1e-4, None)])
        for mode, vs, h in runs:
            out = drake_slope(mode=mode, stiction_tolerance=vs, timestep=h or 0.0, t_end=t_end)
            pred = (ss.engine_creep(f"drake_{mode}", stiction_tolerance=vs)
                    if mode in ("continuous", "tamsi", "lagged") else None)
            label = ("defaults" if (mode == "lagged" and h == 1e-3 and vs == 1e-4) else
                     f"v_s={vs:g} m/s" + (f", h={h:g} s" if h else ""))
            add(f"drake_{mode}", label, "", h, vs, out, pred)
    if "newton" in have:
        # k_f = 1e4 at 1 ms is beyond the explicit step's bound 2 m / (3 n k_f) = 0.17 ms (the
        # box's yaw on its four corners, advise_engine's cost)
        for kf, h in (((1000.0, 1e-3),) if quick else
                      ((1000.0, 1e-3), (1e4, 1e-3), (1e4, 1e-4))):
            out = newton_slope(k_f=kf, timestep=h, t_end=min(t_end, NEWTON_T_END))
            pred = ss.engine_creep("newton_semi_implicit", k_f=kf, n_contacts=out["n_contacts"],
                                   mu=MU, aspect=aspect)
            add("newton_semi_implicit", "defaults" if kf == 1000.0 else
                f"k_f={kf:g} N s/m, h={h:g} s", "", h, kf, out, pred)
    if "bullet" in have:
        for h in ((1 / 240,) if quick else (1 / 960, 1 / 480, 1 / 240, 1 / 120)):
            out = bullet_slope(timestep=h, t_end=t_end)
            add("bullet", "defaults" if h == 1 / 240 else f"h={h:.4g} s", "", h, None, out, None)
    files = [c.write_csv(outdir / "engines_slope.csv",
                         ["engine [-]", "setting [-]", "cone [-]", "timestep [s]",
                          "friction_setting [-]", "n_contacts [-]",
                          "creep_speed [m/s]", "predicted_creep_speed [m/s]",
                          f"creep_{t_end:g}s [m]", f"predicted_creep_{t_end:g}s [m]",
                          "cpu_per_simulated_s [s]"], rows)]

    # the belt: the paper's law (mu_s > mu_k) and the engines' one coefficient, exactly
    series: dict[str, dict[str, np.ndarray]] = {
        "event_driven": exact_belt("event_driven", belt_t_end),
        "moreau": exact_belt("moreau", belt_t_end),
        "event_driven_one_mu": exact_belt("event_driven", belt_t_end, mu_s=MU, mu_k=MU)}
    if "mujoco" in have:
        series["mujoco"] = mujoco_belt(t_end=belt_t_end)
        series["mujoco_elliptic_ir100"] = mujoco_belt(t_end=belt_t_end, cone="elliptic",
                                                      impratio=100.0)
    if "drake" in have:
        # not the lagged model (Drake's default): with the 1e8 kg belt its velocity shows
        # plateaus near +-0.097 m/s that a 1e4 kg belt does not (which then slows by 10 %),
        # an artefact of the mass ratio in SAP, not of friction
        for mode in ("tamsi", "continuous"):
            series[f"drake_{mode}"] = drake_belt(mode=mode, t_end=belt_t_end)
    if "newton" in have:
        series["newton_semi_implicit"] = newton_belt(t_end=belt_t_end)
    if "bullet" in have:
        series["bullet"] = bullet_belt(t_end=belt_t_end)
    brows = []
    for name, sr in series.items():
        summ = stick_summary(sr["t"], sr["x"], sr["v"])
        brows.append([name, summ["amplitude"], summ["period"], summ["stick_per_period"],
                      summ["stick_fraction"], first_release(sr["t"], sr["x"], sr["v"]),
                      sr["cpu_per_s"]])
        c.log(f"  belt {name:22s} amplitude {summ['amplitude'] * 1e3:.4g} mm, period "
              f"{summ['period']:.4g} s, stuck {summ['stick_per_period']:.4g} s a period", quiet)
    files.append(c.write_csv(outdir / "engines_belt.csv",
                             ["run [-]", "amplitude [m]", "period [s]", "stick_per_period [s]",
                              "stick_fraction [-]", "release_mu [-]",
                              "cpu_per_simulated_s [s]"], brows))
    grid = series["event_driven"]["t"]
    cols = {"t [s]": grid}
    for name, sr in series.items():
        cols[f"v_{name} [m/s]"] = np.interp(grid, sr["t"], sr["v"])
    files.append(c.write_columns(outdir / "engines_belt_series.csv", cols))
    files.append(c.write_csv(outdir / "engines_versions.csv", ["engine [-]", "version [-]"],
                             [[k, v] for k, v in {**have, "stickslip": ss.__version__}.items()]))
    files += tables(outdir)
    files += plot(outdir)
    return files


def tables(outdir: Path) -> list[Path]:
    """Markdown tables of the slope and belt CSVs (engines_slope.md, engines_belt.md)."""
    outdir = Path(outdir)
    rows = c.read_csv(outdir / "engines_slope.csv")
    creep_col = next(k for k in rows if k.startswith("creep_") and k.endswith("[m]"))
    pred_col = next(k for k in rows if k.startswith("predicted_creep_") and k.endswith("[m]"))
    cpu = [float(x) for x in rows["cpu_per_simulated_s [s]"]]
    ref = cpu[rows["engine [-]"].index("event_driven")]

    def mm(text: str) -> str:
        return "" if text == "" else f"{float(text) * 1e3:.4g}"

    body = []
    for i, eng in enumerate(rows["engine [-]"]):
        meas, pred = rows[creep_col][i], rows[pred_col][i]
        ratio = f"{float(meas) / float(pred):.4f}" if pred != "" and float(pred) > 0 else ""
        kind = eng + ("_elliptic" if rows["cone [-]"][i] == "elliptic" else "")
        body.append([label(kind), rows["setting [-]"][i], rows["cone [-]"][i], mm(meas),
                     mm(pred) if pred != "" else "no law", ratio, f"{cpu[i] * 1e3:.3g}",
                     f"{cpu[i] / ref:.3g}"])
    t_end = creep_col.split("_")[1].split()[0].replace("s", " s")
    text = c.markdown_table(["engine", "setting", "cone", f"creep in {t_end} [mm]",
                             "predicted [mm]", "measured / predicted",
                             "CPU per simulated s [ms]", "CPU / event_driven's"], body)
    out = [c.write_text(outdir / "engines_slope.md", text)]
    b = c.read_csv(outdir / "engines_belt.csv")

    def num(text: str, fmt: str, scale: float = 1.0) -> str:
        if text in ("", "nan") or math.isnan(float(text)):
            return "-"
        return format(float(text) * scale, fmt)

    bbody = [[label(e), num(b["amplitude [m]"][i], ".4g", 1e3), num(b["period [s]"][i], ".4g"),
              num(b["stick_per_period [s]"][i], ".3g"), num(b["stick_fraction [-]"][i], ".3f"),
              num(b["release_mu [-]"][i], ".3f"),
              num(b["cpu_per_simulated_s [s]"][i], ".3g", 1e3),
              num(b["cpu_per_simulated_s [s]"][i], ".3g",
                  1 / float(b["cpu_per_simulated_s [s]"][b["run [-]"].index("event_driven")]))]
             for i, e in enumerate(b["run [-]"])]
    out.append(c.write_text(outdir / "engines_belt.md", c.markdown_table(
        ["run", "amplitude [mm]", "period [s]", "stuck per period [s]", "stuck fraction",
         "first release: k x / (m g)", "CPU per simulated s [ms]", "CPU / event_driven's"],
        bbody)))
    return out


#: Colour and marker of every engine run kind (fixed across the figures); the exact methods
#: keep the colours of harness.style.
ENGINE_STYLE: dict[str, tuple[str, str]] = {
    "mujoco": (c._style.OKABE_ITO["reddish purple"], "o"),
    "mujoco_elliptic": (c._style.OKABE_ITO["reddish purple"], "s"),
    "drake_continuous": (c._style.OKABE_ITO["bluish green"], "^"),
    "drake_tamsi": (c._style.OKABE_ITO["blue"], "v"),
    "drake_sap": (c._style.OKABE_ITO["sky blue"], "D"),
    "drake_lagged": (c._style.OKABE_ITO["vermillion"], "P"),
    "bullet": (c._style.OKABE_ITO["orange"], "X"),
    "newton_semi_implicit": (c._style.OKABE_ITO["black"], "*")}
LABELS: dict[str, str] = {
    "mujoco": "MuJoCo (pyramidal)", "mujoco_elliptic": "MuJoCo (elliptic)",
    "drake_continuous": "Drake continuous", "drake_tamsi": "Drake TAMSI", "drake_sap": "Drake SAP",
    "drake_lagged": "Drake lagged (default)", "bullet": "Bullet",
    "newton_semi_implicit": "Newton semi-implicit",
    "event_driven_one_mu": "event-driven, μ_s = μ_k",
    "mujoco_elliptic_ir100": "MuJoCo (elliptic, impratio 100)"}


def _default_friction(kind: str, setting: str) -> bool:
    """Whether a run used its engine's default friction setting (impratio 1, v_s = 1e-4)."""
    if setting == "defaults" or kind == "bullet":
        return True
    if kind.startswith("mujoco"):
        return "impratio=1" in setting and "impratio=10" not in setting
    return "v_s=0.0001" in setting


def label(name: str) -> str:
    """Display name of an engine run kind or an exact method."""
    return LABELS.get(name) or c._style.name(name)


#: The rows of engines_slope_creep.png: groups of engines (ENGINE_STYLE's keys).
CREEP_GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("MuJoCo, Drake", ("mujoco", "mujoco_elliptic", "drake_lagged", "drake_tamsi",
                       "drake_continuous", "drake_sap")),
    ("Newton, Bullet", ("newton_semi_implicit", "bullet")))


#: The panels of engines_belt.png: a title and the runs (engines_belt_series.csv's v_<run>)
#: each shows; the engines' panels also show event_driven_one_mu, their best possible cycle.
BELT_PANELS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("stickslip's exact-stick methods", ("event_driven", "moreau", "event_driven_one_mu")),
    ("MuJoCo and Drake", ("mujoco", "mujoco_elliptic_ir100", "drake_tamsi", "drake_continuous")),
    ("Newton and Bullet", ("newton_semi_implicit", "bullet")))


def plot(outdir: str | Path) -> list[Path]:
    """engines_slope_creep.png (left: measured against predicted creep of every engine with a
    law; right: measured creep against the time step at each engine's default friction
    settings) and engines_belt.png (the mass's velocity on the belt), from the CSVs alone."""
    outdir = Path(outdir)
    rows = c.read_csv(outdir / "engines_slope.csv")
    creep_col = next(k for k in rows if k.startswith("creep_") and k.endswith("[m]"))
    pred_col = next(k for k in rows if k.startswith("predicted_creep_") and k.endswith("[m]"))
    t_end = creep_col.split("_")[1].split()[0].replace("s", " s")
    kinds: dict[str, list[int]] = {}
    for i, e in enumerate(rows["engine [-]"]):
        kind = e + ("_elliptic" if rows["cone [-]"][i] == "elliptic" else "")
        kinds.setdefault(kind, []).append(i)
    # a row per group of engines (CREEP_GROUPS), at most six series a panel
    fig, axes = c.new_figure(2, nrows=len(CREEP_GROUPS), height=9.4, sharex="col")
    lim = []
    for row, (group, members) in enumerate(CREEP_GROUPS):
        ax, bx = axes[row]
        for kind in members:
            if kind not in kinds:
                continue
            idx = kinds[kind]
            col, mark = ENGINE_STYLE[kind]
            pairs = [(float(rows[pred_col][i]) * 1e3, abs(float(rows[creep_col][i])) * 1e3)
                     for i in idx if rows[pred_col][i] != ""]
            if pairs:
                p, m = np.array(pairs).T
                lim += [p.min(), p.max(), m.min(), m.max()]
                ax.loglog(p, m, mark, color=col, mfc="none", ms=7, label=label(kind))
            # right panel: every run at the engine's default friction setting, by time step
            steps = [(float(rows["timestep [s]"][i]), abs(float(rows[creep_col][i])) * 1e3)
                     for i in idx if rows["timestep [s]"][i] != ""
                     and _default_friction(kind, rows["setting [-]"][i])]
            steps = sorted({s for s in steps if s[0] > 0})
            if steps:
                h, m = np.array(steps).T
                bx.loglog(h, m, mark + "-", color=col, mfc="none", ms=6, label=label(kind))
        ax.set_title(f"{group}, every run")
        bx.set_title("default friction")
        ax.set_ylabel(f"creep in {t_end} [mm]")
        bx.set_ylabel(f"|creep| in {t_end} [mm]")
        if row == len(CREEP_GROUPS) - 1:
            ax.set_xlabel(f"predicted creep in {t_end} [mm]")
            bx.set_xlabel("time step [s]")
    if lim:
        lo, hi = min(lim) / 1.5, max(lim) * 1.5
        for ax in axes[:, 0]:
            ax.plot([lo, hi], [lo, hi], "-", color="0.5", lw=0.8, zorder=0, label="measured = predicted")
            ax.set_xlim(lo, hi)
            ax.set_ylim(lo, hi)
    c.figure_legend(fig, axes.ravel(), ncol=2)
    files = [c.save_figure(fig, outdir / "engines_slope_creep.png")]

    s = c.read_numeric_csv(outdir / "engines_belt_series.csv")
    # a panel per message (BELT_PANELS, at most five lines each): the library's exact-stick
    # methods, then each group of engines beside the best a one-coefficient engine can do
    # (Coulomb with mu_s = mu_k, grey dashes)
    runs = [key[2:].split(" [")[0] for key in s if key.startswith("v_")]
    unplaced = sorted(set(runs) - {m for _, members in BELT_PANELS for m in members})
    if unplaced:
        raise ValueError(f"engines_belt_series.csv: runs {unplaced} have no panel in BELT_PANELS")
    panels = [(title, [m for m in members if m in runs]) for title, members in BELT_PANELS]
    panels = [panels[0]] + [(title, shown + ["event_driven_one_mu"] * ("event_driven_one_mu" in runs))
                            for title, shown in panels[1:] if shown]     # the engines installed
    fig, _ = c.new_figure(1, nrows=len(panels), height=2.6 * len(panels) + 1.6, sharex=True, sharey=True)
    extra = {"event_driven_one_mu": ("0.45", "--"),
             "mujoco_elliptic_ir100": (c._style.OKABE_ITO["reddish purple"], "--"),
             "newton_semi_implicit": (c._style.OKABE_ITO["black"], "-.")}   # not Moreau's line
    for ax, (title, shown) in zip(fig.axes, panels):
        for name in shown:
            col, ls = extra.get(name, ((ENGINE_STYLE.get(name) or (c._style.color(name),))[0], "-"))
            ax.plot(s["t [s]"], s[f"v_{name} [m/s]"], ls, color=col,
                    lw=2.0 if name == "event_driven" else 1.0, label=label(name))
        ax.set_title(title)
        ax.set_ylabel("velocity of the mass [m/s]")
    fig.axes[-1].set_xlabel("time t [s]")
    c.figure_legend(fig, fig.axes, ncol=1)
    files.append(c.save_figure(fig, outdir / "engines_belt.png"))
    return files


def recorded_but_absent(outdir: Path) -> list[str]:
    """The engines outdir's engines_versions.csv records that are not installed here."""
    path = Path(outdir) / "engines_versions.csv"
    if not path.exists():
        return []
    recorded = c.read_csv(path)["engine [-]"]
    return [name for name in absent_engines() if name in recorded]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.engines [--outdir DIR] [--quick] [--replot] [--force]
    [--threads N] [--quiet]."""
    parser = argparse.ArgumentParser(prog="python -m cases.engines",
                                     description=c.cli_description(__doc__))
    c.add_outdir(parser, help="output directory (default: out/)")
    parser.add_argument("--quick", action="store_true",
                        help="defaults and one setting per engine, t_end 4 s (for tests)")
    parser.add_argument("--replot", action="store_true",
                        help="redraw the figures and tables from the CSVs in --outdir")
    parser.add_argument("--force", action="store_true",
                        help="overwrite results in --outdir made with engines not installed here")
    parser.add_argument("--threads", type=int, default=1,
                        help="accepted for python -m cases; the engines run one after another "
                             "on one thread (each engine's own timing)")
    parser.add_argument("--rocking", action="store_true",
                        help="measure MuJoCo's rocking threshold in solref's damping ratio "
                             "(engines_rocking.csv) instead of the comparison")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    args = parser.parse_args(argv)
    if args.threads < 1:
        parser.error(f"argument --threads: must be >= 1, got {args.threads}")
    if args.replot:
        missing = [f for f in ("engines_slope.csv", "engines_belt.csv", "engines_belt_series.csv")
                   if not (args.outdir / f).exists()]
        if missing:
            parser.error(f"argument --replot: {args.outdir} has no {', '.join(missing)} "
                         f"(run python -m cases.engines --outdir {args.outdir} first)")
        files = tables(args.outdir) + plot(args.outdir)
    elif args.rocking:
        if "mujoco" not in versions():
            parser.error(f"argument --rocking: mujoco is not installed ({INSTALL['mujoco']})")
        return c.finish("engines_rocking", argv, rocking(args.outdir, quiet=args.quiet))
    elif not args.force and (kept := recorded_but_absent(args.outdir)):
        c.log(f"cases.engines: {args.outdir} holds results of {', '.join(kept)}, not installed "
              f"here ({'; '.join(INSTALL[k] for k in kept)}): left as they are (--force "
              f"overwrites them without those engines' rows)", args.quiet)
        return []
    elif args.quick:
        files = run(args.outdir, t_end=4.0, belt_t_end=4.0, quick=True, quiet=args.quiet)
    else:
        files = run(args.outdir, quiet=args.quiet)
    return c.finish("engines", argv, files)


if __name__ == "__main__":
    main()
