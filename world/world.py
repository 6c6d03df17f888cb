"""The World: one pybullet client with the field, robots and ball, stepped in control steps.

The world knows nothing of rules or agents. Anyone (the referee, scenarios, tests) can
place robots and the ball; robots move only by playing motions. Ground truth (poses, ball)
is available here for evaluation; a robot's own view is :meth:`World.sensors` and
:meth:`World.render_camera`.
"""

from __future__ import annotations

import copy
import hashlib
import logging
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from world import rendering
from world.ball import BALL_RGBA, BallState, build_ball
from world.camera_model import NAO_CAMERA, CameraPosition
from world.camera_profiles import CameraEffects, CameraPose, camera_profile
from world.config import RobotSpec, WorldConfig
from world.errors import InvalidCommandError, InvalidPoseError, JointLimitError, UnknownRobotError
from world.field import Pose2D
from world.ground import GroundRenderer
from world.gaits import STANDING
from world.locomotion import LocomotionController, MotionStatus, head_limits_check, torso_heading
from world.motions import Motion
from world.body_poses import BodyPoses
from world.robot_model import ACTUATED_JOINTS, TORSO_CENTER_HEIGHT_M, TeamColor, build_robot, set_team_color
from world.raster.geometry import raster_geometry
from world.raster.renderer import CompiledRenderer
from world.raster.threads import parallel_cameras
from world.scene import SceneBodies, build_scene
from world.static_scene import StaticScene
from world.sensors import (
    GRAVITY_MPS2,
    SensorReading,
    bumpers,
    head_angles,
    mean_angular_velocity,
    sonar_distances,
    sonar_rays_batch,
    to_torso,
)

log = logging.getLogger(__name__)

MAX_ROBOTS = 8
# A locomotion controller's fields that never change (its body, configuration and what follows from
# them): a snapshot leaves them out.
_CONTROLLER_FIXED = ("client", "body", "config", "noise", "_gains")


@dataclass(frozen=True)
class RobotTruth:
    """Ground truth of one robot: torso pose on the field, torso height and tilt."""

    pose: Pose2D
    z_m: float
    tilt_rad: float
    fallen: bool
    team: TeamColor


@dataclass(frozen=True)
class WorldSnapshot:
    """A saved world: the pybullet state plus the controllers' and the world's own state."""

    state_id: int
    time_s: float
    controllers: dict
    teams: dict
    last_toucher: tuple[str | None, float | None]
    previous_velocity: dict
    accelerations: dict
    orientations: dict
    angular_velocities: dict
    rng_state: dict
    imu_rng_state: dict
    imu_bias: dict
    camera_effects: tuple


class World:
    """A field with up to eight robots and a ball, in its own pybullet client.

    ``robots`` fixes the roster for the world's life (the scene is built once; reset
    restores a saved state). ``seed`` seeds the generator of motion noise; pass a
    ``numpy.random.Generator`` to :meth:`reset` to share a match's generator. The camera
    profile (``config.camera_profile``) draws from a stream of its own, spawned from that
    generator's seed sequence without drawing from it.
    """

    def __init__(
        self,
        robots: Sequence[RobotSpec],
        config: WorldConfig | None = None,
        *,
        gui: bool = False,
        seed: int = 0,
    ):
        self.config = config or WorldConfig()
        ids = [spec.robot_id for spec in robots]
        if len(ids) > MAX_ROBOTS or len(set(ids)) != len(ids):
            raise ValueError(f"robots must be at most {MAX_ROBOTS} with unique ids; got {ids}")
        self._client = pb.connect(pb.GUI if gui else pb.DIRECT)
        if self._client < 0:
            raise RuntimeError("could not connect to a pybullet physics server")
        self._closed = False
        self._moves = 0  # placements and restores so far: with the time, the key of the bodies' poses (world.raster)
        try:
            self._build(robots, gui)
        except Exception:
            self.close()
            raise
        self.rng = np.random.default_rng(seed)
        self._camera = CameraEffects(camera_profile(self.config.camera_profile), self.rng.spawn(1)[0])
        self._draw_imu_bias()
        self._initial = self.save_state()

    # ---- construction ---------------------------------------------------------------

    def _build(self, robots: Sequence[RobotSpec], gui: bool) -> None:
        client, cfg = self._client, self.config
        pb.setGravity(0.0, 0.0, -GRAVITY_MPS2, physicsClientId=client)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=cfg.physics.substep_s,
            numSolverIterations=cfg.physics.solver_iterations,
            deterministicOverlappingPairs=1,
            physicsClientId=client,
        )
        # Robots and ball first: TinyRenderer draws in creation order, so the carpet, drawn
        # after them, fails the depth test behind them instead of being shaded twice.
        self._ball = build_ball(client, cfg.field, cfg.ball)
        self._bodies: dict[str, int] = {}
        self._teams: dict[str, TeamColor] = {}
        self._controllers: dict[str, LocomotionController] = {}
        for i, spec in enumerate(robots):
            x = -2.0 + 0.5 * i
            body = build_robot(client, spec.team, x, -2.3, math.pi / 2)
            self._bodies[spec.robot_id] = body
            self._teams[spec.robot_id] = spec.team
            self._controllers[spec.robot_id] = LocomotionController(client, body, cfg.balance, cfg.motion_noise)
            self._reset_joints(body)
        self.scene: SceneBodies = build_scene(client, cfg.field)
        self._ground_ids = (self.scene.ground, self.scene.carpet)
        self._robot_of_body = {body: rid for rid, body in self._bodies.items()}
        self._movable_joints = {body: [j for j in range(pb.getNumJoints(body, physicsClientId=client))
                                       if pb.getJointInfo(body, j, physicsClientId=client)[2] != pb.JOINT_FIXED]
                                for body in self._bodies.values()}
        # Sleeping bodies are not part of a saved state; a world that restores must not sleep.
        for body in (self._ball, *self._bodies.values()):
            pb.changeDynamics(body, -1, activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING, physicsClientId=client)
        self._ground = None
        self._static: StaticScene | None = None  # the broadcast view's hall and goals, drawn once per pose
        self._raster: CompiledRenderer | None = None
        if cfg.render.renderer == "numba":
            self._ground = GroundRenderer(cfg.field, cfg.render, self.scene.floor_half_extent)
            geometry = raster_geometry(cfg.field, self._ball, {self._bodies[rid]: spec.team for rid, spec in
                                                               zip(self._bodies, robots)}, self.scene.goals, BALL_RGBA)
            self._raster = CompiledRenderer(client, geometry, self._ground.hall, cfg.render)
        elif cfg.render.analytic_ground:
            self._ground = GroundRenderer(cfg.field, cfg.render, self.scene.floor_half_extent)
            if not gui:  # the GUI window still shows the textured quads
                for body in self.scene.ground_visuals:
                    pb.changeVisualShape(body, -1, rgbaColor=(0, 0, 0, 0), physicsClientId=client)
                self._static = StaticScene(client, cfg.field, cfg.render, self.scene, self._ground)
        self.time_s = 0.0
        self._last_toucher: tuple[str | None, float | None] = (None, None)
        self._previous_velocity = {rid: (0.0, 0.0, 0.0) for rid in self._bodies}
        self._accelerations = {rid: (0.0, 0.0, 0.0) for rid in self._bodies}
        # each torso's orientation at the end of the last step (or its placement): the gyro's start
        # of the next step, and what the sensors read it from
        self._orientations = {rid: self._orientation(body) for rid, body in self._bodies.items()}
        self._angular_velocities = {rid: (0.0, 0.0, 0.0) for rid in self._bodies}
        # Let the robots settle on their feet before the initial state is saved.
        for _ in range(25):
            self.step()
        self.time_s = 0.0

    # ---- lifecycle ------------------------------------------------------------------

    @property
    def client(self) -> int:
        return self._client

    @property
    def ground(self) -> GroundRenderer | None:
        """The analytic ground and hall (:mod:`world.ground`); None when TinyRenderer draws everything."""
        return self._ground

    @property
    def compiled_renderer(self) -> CompiledRenderer | None:
        """The compiled renderer that draws the cameras (:mod:`world.raster`); None with ``renderer='tiny'``."""
        return self._raster

    @property
    def camera_threads(self) -> bool:
        """Whether the frames of one :meth:`render_cameras` call are drawn, and go through the camera profile,
        on numba's threads (by default where they can be had; the images are the same either way). Worth it
        when the other cores are idle; a match whose controller processes take them draws on one."""
        return self._raster is not None and self._raster.parallel

    @camera_threads.setter
    def camera_threads(self, enabled: bool) -> None:
        if self._raster is not None:
            self._raster.parallel = bool(enabled) and parallel_cameras()

    @property
    def robot_ids(self) -> tuple[str, ...]:
        return tuple(self._bodies)

    def body_id(self, robot_id: str) -> int:
        return self._bodies[self._check_robot(robot_id)]

    @property
    def ball_body_id(self) -> int:
        return self._ball

    def reset(self, rng: np.random.Generator | int | None = None) -> None:
        """Return to the state right after construction; reseed the motion noise if given."""
        self.restore_state(self._initial)
        if isinstance(rng, np.random.Generator):
            self.rng = rng
        elif rng is not None:
            self.rng = np.random.default_rng(rng)
        if rng is not None:
            self._camera.reseed(self.rng.spawn(1)[0])  # a child stream: the physics' draws are not touched
            self._draw_imu_bias()

    def _draw_imu_bias(self) -> None:
        """A generator of its own for the inertial sensors' noise (seeded from the world's), and
        each robot's constant gyro and accelerometer biases."""
        self._imu_rng = np.random.default_rng(int(self.rng.integers(0, 2**63)))
        noise = self.config.imu_noise
        self._imu_bias = {
            rid: (
                tuple(float(v) for v in self._imu_rng.normal(0.0, 1.0, 3) * noise.gyro_bias_sigma_radps),
                tuple(float(v) for v in self._imu_rng.normal(0.0, 1.0, 3) * noise.accelerometer_bias_sigma_mps2),
            )
            for rid in self._bodies
        }

    def save_state(self) -> WorldSnapshot:
        controllers = {
            rid: {k: copy.deepcopy(v) for k, v in vars(c).items() if k not in _CONTROLLER_FIXED}
            for rid, c in self._controllers.items()
        }
        return WorldSnapshot(
            state_id=pb.saveState(physicsClientId=self._client),
            time_s=self.time_s,
            controllers=controllers,
            teams=dict(self._teams),
            last_toucher=self._last_toucher,
            previous_velocity=dict(self._previous_velocity),
            accelerations=dict(self._accelerations),
            orientations=dict(self._orientations),
            angular_velocities=dict(self._angular_velocities),
            rng_state=copy.deepcopy(self.rng.bit_generator.state),
            imu_rng_state=copy.deepcopy(self._imu_rng.bit_generator.state),
            imu_bias=copy.deepcopy(self._imu_bias),
            camera_effects=self._camera.save(),
        )

    def discard_state(self, snapshot: WorldSnapshot) -> None:
        """Free the memory of a saved state that will not be restored again."""
        if snapshot is self._initial:
            raise ValueError("the initial state is kept for reset() and cannot be discarded")
        pb.removeState(snapshot.state_id, physicsClientId=self._client)

    def restore_state(self, snapshot: WorldSnapshot) -> None:
        self._moves += 1
        self._clear_contact_caches()
        pb.restoreState(stateId=snapshot.state_id, physicsClientId=self._client)
        self.time_s = snapshot.time_s
        for rid, fields in snapshot.controllers.items():
            controller = self._controllers[rid]
            for key, value in fields.items():
                setattr(controller, key, copy.deepcopy(value))
            controller.resend_motor_targets()  # motor targets are not part of a pybullet state
        for rid, team in snapshot.teams.items():
            self.set_team_color(rid, team)
        self._last_toucher = snapshot.last_toucher
        self._previous_velocity = dict(snapshot.previous_velocity)
        self._accelerations = dict(snapshot.accelerations)
        self._orientations = dict(snapshot.orientations)
        self._angular_velocities = dict(snapshot.angular_velocities)
        self.rng.bit_generator.state = copy.deepcopy(snapshot.rng_state)
        self._imu_rng.bit_generator.state = copy.deepcopy(snapshot.imu_rng_state)
        self._imu_bias = copy.deepcopy(snapshot.imu_bias)
        self._camera.restore(snapshot.camera_effects)

    def _clear_contact_caches(self) -> None:
        """Drop cached contact pairs, which a restored state does not overwrite.

        Without this, a pair that touched before the restore (two robots that collided)
        keeps a stale manifold that changes the solver order, and a restored run differs
        from the first run in the last bits.
        """
        for i, body in enumerate((self._ball, *self._bodies.values())):
            pb.resetBasePositionAndOrientation(body, (1000.0 + 10.0 * i, 1000.0, 0.0), (0, 0, 0, 1), physicsClientId=self._client)
        pb.performCollisionDetection(physicsClientId=self._client)

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            if getattr(self, "_static", None) is not None:
                self._static.close()
            pb.disconnect(physicsClientId=self._client)

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self) -> None:  # a world left open must not leak its server
        try:
            self.close()
        except Exception:  # interpreter shutdown: pybullet may already be gone
            pass

    # ---- placing things -------------------------------------------------------------

    def place_robot(self, robot_id: str, pose: Pose2D) -> None:
        """Put a robot standing upright at ``pose`` (field frame), at rest.

        Clears its motion and fall state and levels its head (yaw 0, pitch 0); the camera
        position is kept. A head target takes a few steps to be reached after this.
        """
        self._moves += 1
        body = self.body_id(robot_id)
        self._check_position(f"robot {robot_id!r} pose", pose.x, pose.y, extra=(pose.theta,))
        orientation = pb.getQuaternionFromEuler((0.0, 0.0, pose.theta))
        pb.resetBasePositionAndOrientation(
            body, (pose.x, pose.y, TORSO_CENTER_HEIGHT_M + 0.002), orientation, physicsClientId=self._client
        )
        pb.resetBaseVelocity(body, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), physicsClientId=self._client)
        self._reset_joints(body)
        controller = self._controllers[robot_id]
        controller.reset()
        controller.set_head(0.0, 0.0)
        self._previous_velocity[robot_id] = (0.0, 0.0, 0.0)
        self._accelerations[robot_id] = (0.0, 0.0, 0.0)
        self._orientations[robot_id] = orientation
        self._angular_velocities[robot_id] = (0.0, 0.0, 0.0)
        self._camera.forget(robot_id)  # a placed camera did not move there during an exposure

    def place_ball(self, x: float, y: float, vx: float = 0.0, vy: float = 0.0) -> None:
        """Put the ball on the ground at (x, y) with planar velocity (vx, vy) m/s."""
        self._moves += 1
        self._check_position("ball position", x, y, extra=(vx, vy))
        r = self.config.field.ball_radius
        pb.resetBasePositionAndOrientation(self._ball, (x, y, r), (0, 0, 0, 1), physicsClientId=self._client)
        pb.resetBaseVelocity(self._ball, (vx, vy, 0.0), (-vy / r, vx / r, 0.0), physicsClientId=self._client)

    def set_team_color(self, robot_id: str, team: TeamColor) -> None:
        """Change a robot's waistband colour (teams swap colours at half-time)."""
        body = self.body_id(robot_id)
        if not isinstance(team, TeamColor):
            raise InvalidCommandError(f"team colour {team!r} is not one of {[t.value for t in TeamColor]}")
        self._teams[robot_id] = team
        set_team_color(self._client, body, team)

    # ---- commands ---------------------------------------------------------------------

    def command_motion(self, robot_id: str, motion: Motion | str) -> bool:
        """Start a predefined motion; False if refused (a fallen robot can only stand up).

        Commanding the motion that is already playing lets it continue; another motion
        interrupts it.
        """
        self._check_robot(robot_id)
        parsed = Motion.parse(motion)
        if parsed is Motion.WALK:
            raise InvalidCommandError("motion 'walk' needs a velocity: use command_walk(robot_id, vx, vy, omega)")
        return self._controllers[robot_id].start(parsed, self.time_s, self.rng)

    def command_walk(self, robot_id: str, vx: float, vy: float, omega: float) -> bool:
        """Walk continuously at (vx, vy) m/s in the torso frame, turning at ``omega`` rad/s."""
        self._check_robot(robot_id)
        self.config.walk_limits.check(vx, vy, omega)
        return self._controllers[robot_id].start(Motion.WALK, self.time_s, self.rng, walk=(vx, vy, omega))

    def set_head(self, robot_id: str, yaw_rad: float, pitch_rad: float) -> None:
        """Head joint targets in radians (yaw CCW positive, pitch positive looks down)."""
        self._check_robot(robot_id)
        problem = head_limits_check(yaw_rad, pitch_rad)
        if problem:
            raise JointLimitError(f"robot {robot_id!r}: {problem}")
        self._controllers[robot_id].set_head(yaw_rad, pitch_rad)

    def set_camera(self, robot_id: str, camera: CameraPosition) -> None:
        self._check_robot(robot_id)
        if not isinstance(camera, CameraPosition):
            raise InvalidCommandError(f"camera {camera!r} is not one of {[c.value for c in CameraPosition]}")
        self._controllers[robot_id].camera = camera

    # ---- time -------------------------------------------------------------------------

    def step(self, control_steps: int = 1) -> None:
        """Advance the simulation by whole control steps (40 ms each by default)."""
        physics = self.config.physics
        dt = physics.substep_s
        client = self._client
        for _ in range(control_steps):
            for _ in range(physics.substeps):
                for controller in self._controllers.values():
                    controller.substep(self.time_s, dt)
                pb.stepSimulation(physicsClientId=client)
                self.time_s += dt
                self._record_ball_touch()
            self._update_inertial(physics.control_step_s)

    def _record_ball_touch(self) -> None:
        for contact in pb.getContactPoints(bodyA=self._ball, physicsClientId=self._client):
            robot = self._robot_of_body.get(contact[2])
            if robot is not None:
                self._last_toucher = (robot, self.time_s)

    def _update_inertial(self, dt: float) -> None:
        """The inertial unit's readings of the control step just played, as means over it: the
        acceleration from the change of velocity (world frame), the angular velocity from the
        rotation between the step's start and end (torso frame). An instant's angular velocity
        would alias the yaw jitter of a torso jostled by contact into drift."""
        for rid, body in self._bodies.items():
            linear, _ = pb.getBaseVelocity(body, physicsClientId=self._client)
            previous = self._previous_velocity[rid]
            self._accelerations[rid] = tuple((a - b) / dt for a, b in zip(linear, previous))
            self._previous_velocity[rid] = linear
            orientation = self._orientation(body)
            self._angular_velocities[rid] = mean_angular_velocity(self._orientations[rid], orientation, dt)
            self._orientations[rid] = orientation

    def _orientation(self, body: int) -> tuple[float, float, float, float]:
        return pb.getBasePositionAndOrientation(body, physicsClientId=self._client)[1]

    # ---- what robots sense ----------------------------------------------------------

    def render_camera(self, robot_id: str) -> np.ndarray:
        """The robot's 160x120 RGB camera image (uint8, rows top to bottom), through the world's camera
        profile (:mod:`world.camera_profiles`; ``clean``: as rendered). Each call is one frame of the
        robot's camera: the profile's image motion and lost frames follow from the robot's previous call."""
        controller = self._controllers[self._check_robot(robot_id)]
        if self._raster is not None:
            pose = self.camera_pose(robot_id)
            return self._through_profile(robot_id, self._compiled_frames([pose])[0][0], pose)
        image = rendering.render_robot_camera(
            self._client, controller.body, controller.camera, self.config.render, self._ground
        )
        if self._camera.profile.clean:
            return image
        return self._through_profile(robot_id, image, self.camera_pose(robot_id))

    def render_cameras(self, robot_ids: Sequence[str]) -> Iterator[tuple[str, np.ndarray]]:
        """Each robot's camera image (as :meth:`render_camera`), as ``(robot_id, image)`` pairs in
        ``robot_ids`` order; the compiled renderer draws them all in one call, and the camera profile
        takes them all in another."""
        ids = [self._check_robot(rid) for rid in robot_ids]
        if self._raster is not None:
            poses = [self.camera_pose(rid) for rid in ids]
            images = self._compiled_frames(poses)[0]
            if not self._camera.profile.clean:
                taken = [CameraPose(self.time_s, self._controllers[rid].camera, *pose) for rid, pose in zip(ids, poses)]
                images = self._camera.apply_many(list(zip(ids, images, taken)), self._raster.parallel)
            yield from zip(ids, images)
            return
        for rid in ids:
            yield rid, self.render_camera(rid)

    def _through_profile(self, robot_id: str, image: np.ndarray, pose: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        """``image``, rendered from the camera ``pose`` of ``robot_id``, as the camera profile delivers it."""
        if self._camera.profile.clean:
            return image
        camera = self._controllers[robot_id].camera
        return self._camera.apply(robot_id, image, CameraPose(self.time_s, camera, *pose))

    def render_camera_at(self, rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
        """The 160x120 RGB image of a robot camera at a pose (rotation camera->world, position m), as rendered
        (no camera profile: no robot's camera took it)."""
        cam = NAO_CAMERA
        if self._raster is not None:
            return self._compiled_frames([(np.asarray(rotation, float), np.asarray(position, float))])[0][0]
        return rendering.render(self._client, np.asarray(rotation, float), np.asarray(position, float),
                                cam.width_px, cam.height_px, cam.vertical_fov_rad, self.config.render, self._ground)

    def camera_labels(self, robot_id: str) -> tuple[np.ndarray, np.ndarray]:
        """The robot's camera image as rendered (before the camera profile, which this does not advance) and
        what each pixel shows: pybullet's segmentation label (body id plus (link index + 1) << 24, -1 for the
        hall), (120, 160) int32. Needs the compiled renderer."""
        if self._raster is None:
            raise ValueError("camera_labels needs RenderConfig(renderer='numba')")
        images, labels = self._compiled_frames([self.camera_pose(self._check_robot(robot_id))])
        return images[0], labels[0]

    def _compiled_frames(self, cameras: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
        cam = NAO_CAMERA
        teams = {self._bodies[rid]: team for rid, team in self._teams.items()}
        return self._raster.frames(cameras, cam.width_px, cam.height_px, cam.vertical_fov_rad, teams,
                                   poses_key=(self.time_s, self._moves))

    def body_poses(self) -> BodyPoses:
        """Every robot's base pose and joint angles, the ball's pose and the team colours (see :class:`BodyPoses`)."""
        client, robots = self._client, []
        for rid, body in self._bodies.items():
            position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=client)
            joints = self._movable_joints[body]
            angles = tuple(state[0] for state in pb.getJointStates(body, joints, physicsClientId=client))
            robots.append((position, orientation, angles))
        ball = pb.getBasePositionAndOrientation(self._ball, physicsClientId=client)
        return BodyPoses(tuple(robots), ball, tuple(self._teams[rid] for rid in self._bodies))

    def state_digest(self) -> str:
        """A short hash (16 hex digits) of the world's physical state: the time, every robot's base pose and
        velocity and its joints' angles and speeds, the ball's pose and velocity, bit for bit. Two runs whose
        digests differ at a step first differed in the step before it (a debugging aid across machines)."""
        client, numbers = self._client, [self.time_s]
        for body in (*self._bodies.values(), self._ball):
            position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=client)
            linear, angular = pb.getBaseVelocity(body, physicsClientId=client)
            numbers += (*position, *orientation, *linear, *angular)
            joints = self._movable_joints.get(body)
            if joints:
                for state in pb.getJointStates(body, joints, physicsClientId=client):
                    numbers += state[:2]
        return hashlib.blake2b(np.asarray(numbers, np.float64).tobytes(), digest_size=8).hexdigest()

    def set_body_poses(self, poses: BodyPoses) -> None:
        """Put every body where ``poses`` says, at rest (for a copy of a world that only draws: no physics is
        kept)."""
        self._moves += 1
        client = self._client
        if len(poses.robots) != len(self._bodies) or len(poses.teams) != len(self._bodies):
            raise ValueError(f"poses of {len(poses.robots)} robots for a world of {len(self._bodies)}")
        for (rid, body), (position, orientation, angles), team in zip(self._bodies.items(), poses.robots, poses.teams):
            pb.resetBasePositionAndOrientation(body, position, orientation, physicsClientId=client)
            joints = self._movable_joints[body]
            pb.resetJointStatesMultiDof(body, joints, [[angle] for angle in angles], [[0.0]] * len(joints),
                                        physicsClientId=client)
            if self._teams[rid] is not team:
                self.set_team_color(rid, team)
        pb.resetBasePositionAndOrientation(self._ball, *poses.ball, physicsClientId=client)
        self._camera.forget()

    def sensors(self, robot_id: str) -> SensorReading:
        return self.sensors_all((robot_id,))[robot_id]

    def sensors_all(self, robot_ids: Sequence[str] | None = None) -> dict[str, SensorReading]:
        """Sensor readings of several robots, with one batched ray test for all sonars."""
        ids = list(self.robot_ids if robot_ids is None else [self._check_robot(r) for r in robot_ids])
        client = self._client
        hits = []
        if ids:
            starts, ends = sonar_rays_batch(client, [self._bodies[rid] for rid in ids], self.config.sonar)
            hits = pb.rayTestBatch(starts.tolist(), ends.tolist(), physicsClientId=client)
        rays_per_robot = 4 * len(self.config.sonar.cone_offsets_rad)
        noise = self.config.imu_noise
        # every robot's white noise in one draw, in the order of single draws: accelerometer, then gyro
        white = self._imu_rng.normal(0.0, 1.0, (len(ids), 2, 3))
        white[:, 0] *= noise.accelerometer_noise_sigma_mps2
        white[:, 1] *= noise.gyro_noise_sigma_radps
        white = white.tolist()
        readings = {}
        for i, rid in enumerate(ids):
            body = self._bodies[rid]
            controller = self._controllers[rid]
            m = pb.getMatrixFromQuaternion(self._orientations[rid])
            ax, ay, az = self._accelerations[rid]
            yaw, pitch = head_angles(client, body)
            gyro_bias, accelerometer_bias = self._imu_bias[rid]
            readings[rid] = SensorReading(
                head_yaw_rad=yaw,
                head_pitch_rad=pitch,
                camera=controller.camera,
                accelerometer_mps2=_imu_reading(to_torso(m, (ax, ay, az + GRAVITY_MPS2)), accelerometer_bias,
                                                white[i][0]),
                gyro_radps=_imu_reading(self._angular_velocities[rid], gyro_bias, white[i][1]),
                sonar_m=sonar_distances(hits[i * rays_per_robot : (i + 1) * rays_per_robot], self.config.sonar),
                bumpers=bumpers(client, body, self._ground_ids),
                motion=controller.status(self.time_s),
            )
        return readings

    def motion_status(self, robot_id: str) -> MotionStatus:
        return self._controllers[self._check_robot(robot_id)].status(self.time_s)

    def camera_pose(self, robot_id: str) -> tuple[np.ndarray, np.ndarray]:
        """Ground-truth world pose of the robot's active camera (rotation cam->world, position)."""
        controller = self._controllers[self._check_robot(robot_id)]
        return rendering.camera_pose(self._client, controller.body, controller.camera)

    # ---- ground truth ----------------------------------------------------------------

    def robot_truth(self, robot_id: str) -> RobotTruth:
        body = self.body_id(robot_id)
        position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=self._client)
        m = pb.getMatrixFromQuaternion(orientation)
        return RobotTruth(
            pose=Pose2D(position[0], position[1], torso_heading(m)),
            z_m=position[2],
            tilt_rad=math.acos(max(-1.0, min(1.0, m[8]))),
            fallen=self._controllers[robot_id].fallen,
            team=self._teams[robot_id],
        )

    def robot_pose(self, robot_id: str) -> Pose2D:
        return self.robot_truth(robot_id).pose

    def ball(self) -> BallState:
        position, _ = pb.getBasePositionAndOrientation(self._ball, physicsClientId=self._client)
        velocity, _ = pb.getBaseVelocity(self._ball, physicsClientId=self._client)
        toucher, touch_time = self._last_toucher
        return BallState(*position, *velocity, last_toucher=toucher, last_touch_time_s=touch_time)

    def render_overview(self, **kwargs) -> np.ndarray:
        """A broadcast view of the field (see :func:`world.rendering.render_overview`); its goals and hall are
        drawn once per camera pose (:mod:`world.static_scene`)."""
        if self._raster is not None:
            teams = {self._bodies[rid]: team for rid, team in self._teams.items()}
            return rendering.compiled_overview(self._raster, teams, poses_key=(self.time_s, self._moves), **kwargs)
        return rendering.render_overview(self._client, self.config.render, self._ground, static=self._static, **kwargs)

    # ---- checks ----------------------------------------------------------------------

    def _check_robot(self, robot_id: str) -> str:
        if robot_id not in self._bodies:
            raise UnknownRobotError(robot_id, self.robot_ids)
        return robot_id

    def _check_position(self, what: str, x: float, y: float, extra: tuple[float, ...] = ()) -> None:
        values = (x, y, *extra)
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            raise InvalidPoseError(f"{what} {values!r} must be finite numbers")
        field, margin = self.config.field, self.config.off_world_margin_m
        hx, hy = field.carpet_half_length + margin, field.carpet_half_width + margin
        if abs(x) > hx or abs(y) > hy:
            raise InvalidPoseError(f"{what} (x={x}, y={y}) outside the world |x| <= {hx}, |y| <= {hy} m")

    def _reset_joints(self, body: int) -> None:
        for joint in ACTUATED_JOINTS:
            pb.resetJointState(body, int(joint), STANDING.get(joint, 0.0), 0.0, physicsClientId=self._client)


def _imu_reading(true: tuple[float, float, float], bias: tuple[float, ...], white: list[float]
                 ) -> tuple[float, float, float]:
    """A reading: the true value plus the robot's bias plus its white noise (drawn even when zero)."""
    return (true[0] + bias[0] + white[0], true[1] + bias[1] + white[1], true[2] + bias[2] + white[2])
