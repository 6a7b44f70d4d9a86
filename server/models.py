"""Request and response bodies: pydantic models whose limits are the service's input rules.

Every number must be finite and within a sane range, every array of the stated length; the
library's own rules (a proper rotation, mu_spin 0 when mu is 0, a set's dimensions agreeing) are
checked when the request is turned into library objects, and reported the same way (server.app).
Strict mode: a string is not a number. Unknown fields are refused, so a misspelt option is an
error rather than silently the default.
"""
from typing import Annotated, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from . import settings

COORD = 1e6            # bound on any coordinate, matrix entry or radius: keeps squares finite
WRENCH = 1e9           # bound on a wrench entry
MAX_DIM = 16           # dimension of a set given to ray shooting
MAX_VERTICES = 10000   # vertices of one polytope
MAX_DEPTH = 16         # nesting of hulls, sums and affine images

Coord = Annotated[float, Field(ge=-COORD, le=COORD)]
Radius = Annotated[float, Field(ge=0.0, le=COORD)]
Friction = Annotated[float, Field(ge=0.0, le=1e3)]
Vec3 = Annotated[list[Coord], Field(min_length=3, max_length=3)]
Mat3 = Annotated[list[Vec3], Field(min_length=3, max_length=3)]
Wrench = Annotated[list[Annotated[float, Field(ge=-WRENCH, le=WRENCH)]],
                   Field(min_length=6, max_length=6)]
Method = Literal["gjk", "ie", "zc", "bi-gjk", "zc-ie", "zc-ie-paper", "zc-ie-newton"]
Norm = Literal["L1", "Linf"]
Magnitude = Literal["normal", "full"]
Eps = Annotated[float, Field(ge=1e-15, le=0.1, description="relative tolerance, in [1e-15, 0.1]")]
MaxIter = Annotated[int, Field(ge=1, le=100000)]
Length = Annotated[float, Field(gt=0.0, le=COORD, description=(
    "the grasp's characteristic length L (graspforce.Grasp): min_force works in the units "
    "(force, torque / L); when absent, derived from the contacts"))]


class Model(BaseModel):
    model_config = ConfigDict(strict=True, extra="forbid", allow_inf_nan=False)


def _rows(matrix, name, max_cols=MAX_DIM):
    """The common row length of a matrix, or the error naming the rule."""
    lengths = {len(row) for row in matrix}
    if len(lengths) != 1:
        raise ValueError(f"{name}: all rows must have the same length")
    (n,) = lengths
    if not 1 <= n <= max_cols:
        raise ValueError(f"{name}: rows must have 1 to {max_cols} entries, got {n}")
    return n


# -- sets ----------------------------------------------------------------------------------------
class PolytopeIn(Model):
    """CH of the rows of `vertices` (k, n)."""
    type: Literal["polytope"]
    vertices: Annotated[list[list[Coord]], Field(min_length=1, max_length=MAX_VERTICES)]

    @field_validator("vertices")
    @classmethod
    def _rectangular(cls, v):
        _rows(v, "vertices")
        return v


class EllipsoidIn(Model):
    """{center + shape x : |x| <= 1}, shape (n, k)."""
    type: Literal["ellipsoid"]
    center: Annotated[list[Coord], Field(min_length=1, max_length=MAX_DIM)]
    shape: Annotated[list[list[Coord]], Field(min_length=1, max_length=MAX_DIM)]

    @field_validator("shape")
    @classmethod
    def _rectangular(cls, v):
        _rows(v, "shape")
        return v


class BallIn(Model):
    type: Literal["ball"]
    center: Annotated[list[Coord], Field(min_length=1, max_length=MAX_DIM)]
    radius: Radius


class BoxIn(Model):
    """{center + rotation x : |x_i| <= half_extents_i}."""
    type: Literal["box"]
    half_extents: Annotated[list[Radius], Field(min_length=1, max_length=MAX_DIM)]
    center: Annotated[list[Coord], Field(min_length=1, max_length=MAX_DIM)] | None = None
    rotation: Annotated[list[list[Coord]], Field(min_length=1, max_length=MAX_DIM)] | None = None


class TruncatedConeIn(Model):
    type: Literal["truncated_cone"]
    bottom_radius: Radius
    top_radius: Radius
    height: Radius


class CapsuleIn(Model):
    type: Literal["capsule"]
    radius: Radius
    length: Radius


class HullIn(Model):
    """Convex hull of the union of `sets` (all of one dimension)."""
    type: Literal["hull"]
    sets: Annotated[list["SetIn"], Field(min_length=1, max_length=64)]


class MinkowskiSumIn(Model):
    type: Literal["minkowski_sum"]
    sets: Annotated[list["SetIn"], Field(min_length=1, max_length=64)]


class AffineIn(Model):
    """{matrix a + offset : a in set}; matrix (m, n) with n the set's dimension."""
    type: Literal["affine"]
    matrix: Annotated[list[list[Coord]], Field(min_length=1, max_length=MAX_DIM)]
    set: "SetIn"
    offset: Annotated[list[Coord], Field(min_length=1, max_length=MAX_DIM)] | None = None

    @field_validator("matrix")
    @classmethod
    def _rectangular(cls, v):
        _rows(v, "matrix")
        return v


SetIn = Annotated[Union[PolytopeIn, EllipsoidIn, BallIn, BoxIn, TruncatedConeIn, CapsuleIn,
                        HullIn, MinkowskiSumIn, AffineIn], Field(discriminator="type")]
for _m in (HullIn, MinkowskiSumIn, AffineIn):
    _m.model_rebuild()


def check_set_size(s, name):
    """At most GRASPFORCE_MAX_SET_LEAVES primitive sets, nested at most MAX_DEPTH deep."""
    limit = settings.current.max_set_leaves
    leaves = 0
    stack = [(s, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise ValueError(f"{name}: sets may be nested at most {MAX_DEPTH} deep")
        if isinstance(node, (HullIn, MinkowskiSumIn)):
            stack.extend((child, depth + 1) for child in node.sets)
        elif isinstance(node, AffineIn):
            stack.append((node.set, depth + 1))
        else:
            leaves += 1
            if leaves > limit:
                raise ValueError(f"{name}: at most {limit} primitive sets "
                                 "(GRASPFORCE_MAX_SET_LEAVES)")


# -- grasps --------------------------------------------------------------------------------------
class ContactIn(Model):
    """A contact: position, inward normal (nonzero), friction mu >= 0 and torsional friction
    mu_spin >= 0 in metres (0 when mu is 0), each 0 or at least 1e-9; tangents (o, t)
    optional, unit, o x t = normal."""
    position: Vec3
    normal: Vec3
    mu: Friction
    mu_spin: Friction = 0.0
    tangents: Annotated[list[Vec3], Field(min_length=2, max_length=2)] | None = None

    @field_validator("mu", "mu_spin")
    @classmethod
    def _zero_or_sane(cls, v, info):
        # a coefficient of 1e-300 is a zero meant otherwise: (mu / mu_spin)^2 would overflow
        if 0.0 < v < 1e-9:
            raise ValueError(f"{info.field_name}: must be 0 or at least 1e-9, got {v!r}")
        return v

    @field_validator("normal")
    @classmethod
    def _nonzero(cls, v):
        if sum(x * x for x in v) <= 1e-24:
            raise ValueError("normal: must be a nonzero vector")
        return v


Contacts = Annotated[list[ContactIn], Field(min_length=1)]


def _check_contacts(v):
    limit = settings.current.max_contacts
    if len(v) > limit:
        raise ValueError(f"contacts: at most {limit} contacts (GRASPFORCE_MAX_CONTACTS), "
                         f"got {len(v)}")
    return v


EXAMPLE_CONTACTS = [
    {"position": [0.05, 0.01, 0.0], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
    {"position": [0.05, -0.01, 0.01], "normal": [-1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
    {"position": [-0.05, 0.01, 0.0], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01},
    {"position": [-0.05, -0.01, -0.01], "normal": [1, 0, 0], "mu": 0.5, "mu_spin": 0.01}]


class ForceOptimizationIn(Model):
    """Minimal contact forces resisting w_ext (graspforce.Grasp.min_force)."""
    model_config = ConfigDict(json_schema_extra={"examples": [{
        "contacts": EXAMPLE_CONTACTS, "w_ext": [0, 0, -9.81, 0, 0, 0], "norm": "L1",
        "magnitude": "normal", "method": "zc-ie", "eps": 1e-9}]})
    contacts: Contacts
    length: Length | None = None
    w_ext: Wrench
    norm: Norm = "L1"
    magnitude: Magnitude = "normal"
    method: Method = "zc-ie"
    eps: Eps = 1e-9
    max_iter: MaxIter = 10000
    compare: Annotated[list[Literal["clarabel", "osqp"]], Field(max_length=2)] = []

    _contacts = field_validator("contacts")(classmethod(lambda cls, v: _check_contacts(v)))


class SampleIn(Model):
    """count wrenches: mean + normal noise of force_scale (forces) and torque_scale (torques)
    from seed (graspforce.batch.wrenches.gaussian)."""
    count: Annotated[int, Field(ge=1)]
    seed: Annotated[int, Field(ge=0, le=2**63 - 1)] = 0
    force_scale: Annotated[float, Field(ge=0.0, le=WRENCH)] = 1.0
    torque_scale: Annotated[float, Field(ge=0.0, le=WRENCH)] = 0.05
    mean: Wrench | None = None


class BatchIn(Model):
    """min_force for one grasp and many wrenches: `wrenches` given, or `sample` drawn."""
    model_config = ConfigDict(json_schema_extra={"examples": [{
        "contacts": EXAMPLE_CONTACTS, "sample": {"count": 100, "seed": 1, "force_scale": 3.0,
                                                 "torque_scale": 0.05,
                                                 "mean": [0, 0, -9.81, 0, 0, 0]},
        "forces": False}]})
    contacts: Contacts
    length: Length | None = None
    wrenches: Annotated[list[Wrench], Field(min_length=1)] | None = None
    sample: SampleIn | None = None
    norm: Norm = "L1"
    magnitude: Magnitude = "normal"
    method: Method = "zc-ie"
    eps: Eps = 1e-9
    max_iter: MaxIter = 10000
    forces: bool = False

    _contacts = field_validator("contacts")(classmethod(lambda cls, v: _check_contacts(v)))

    @field_validator("wrenches")
    @classmethod
    def _batch_size(cls, v):
        limit = settings.current.max_batch
        if v is not None and len(v) > limit:
            raise ValueError(f"wrenches: at most {limit} wrenches (GRASPFORCE_MAX_BATCH), "
                             f"got {len(v)}")
        return v

    @model_validator(mode="after")
    def _one_source(self):
        if (self.wrenches is None) == (self.sample is None):
            raise ValueError("wrenches, sample: give exactly one of them")
        limit = settings.current.max_batch
        if self.sample is not None and self.sample.count > limit:
            raise ValueError(f"sample.count: at most {limit} wrenches (GRASPFORCE_MAX_BATCH), "
                             f"got {self.sample.count}")
        return self


class ForceClosureIn(Model):
    """Force closure (graspforce.Grasp.is_force_closure) and, if `quality`, the bracketed
    Ferrari-Canny quality (Grasp.quality) with eps its relative bracket width."""
    model_config = ConfigDict(json_schema_extra={"examples": [{
        "contacts": EXAMPLE_CONTACTS, "quality": True, "eps": 1e-2}]})
    contacts: Contacts
    length: Length | None = None
    quality: bool = True
    norm: Norm = "L1"
    magnitude: Magnitude = "normal"
    eps: Annotated[float, Field(ge=1e-4, le=0.5)] = 1e-3
    tol: Annotated[float, Field(ge=1e-15, le=1e-3)] = 1e-9
    max_iter: Annotated[int, Field(ge=1, le=5000)] = 500

    _contacts = field_validator("contacts")(classmethod(lambda cls, v: _check_contacts(v)))


class RayShootIn(Model):
    """The farthest point of `set` on the ray {lambda r : lambda >= 0}
    (graspforce.shooting.ray_shoot)."""
    model_config = ConfigDict(json_schema_extra={"examples": [{
        "set": {"type": "hull", "sets": [
            {"type": "ellipsoid", "center": [0, 0, 0], "shape": [[1, 0, 0], [0, 2, 0],
                                                                 [0, 0, 0.5]]},
            {"type": "polytope", "vertices": [[2, 0, 0], [0, 0, 1.5], [-1, -1, -1]]}]},
        "r": [1.0, 0.5, 0.2], "method": "zc-ie", "eps": 1e-9}]})
    set: SetIn
    r: Annotated[list[Coord], Field(min_length=1, max_length=MAX_DIM)]
    method: Method = "zc-ie"
    eps: Eps = 1e-9
    max_iter: MaxIter = 10000

    @model_validator(mode="after")
    def _size(self):
        check_set_size(self.set, "set")
        return self


class PoseIn(Model):
    """(R, p): a proper rotation matrix and a translation."""
    rotation: Mat3
    translation: Vec3


class GrowthDistanceIn(Model):
    """The growth distance of two 3-D shapes (their local origins interior) at their poses
    (graspforce.growth_distance)."""
    model_config = ConfigDict(json_schema_extra={"examples": [{
        "a": {"type": "ellipsoid", "center": [0, 0, 0],
              "shape": [[0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.3]]},
        "pose_a": {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "translation": [0, 0, 0]},
        "b": {"type": "truncated_cone", "bottom_radius": 0.1, "top_radius": 0.05,
              "height": 0.2},
        "pose_b": {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "translation": [0.5, 0, 0]},
        "method": "zc-ie", "eps": 1e-9}]})
    a: SetIn
    pose_a: PoseIn
    b: SetIn
    pose_b: PoseIn
    method: Method = "zc-ie"
    eps: Eps = 1e-9
    max_iter: MaxIter = 10000
    touching_tol: Annotated[float, Field(ge=0.0, le=0.5)] = 1e-9

    @model_validator(mode="after")
    def _size(self):
        check_set_size(self.a, "a")
        check_set_size(self.b, "b")
        return self


# -- responses -------------------------------------------------------------------------------------
# a number that JSON cannot carry (an infinite sigma) is null
Num = float | None
Matrix = list[list[float]]


class MinForceOut(BaseModel):
    """graspforce.MinForce: sigma (null when infinite: infeasible or undecided) and its
    certified lower bound, the local forces (m, 4), world forces (m, 3), wrenches (m, 6) and
    their resultant (-w_ext)."""
    feasible: bool
    status: Literal["optimal", "infeasible", "max_iter"]
    sigma: Num
    sigma_lower: Num
    norm: Norm
    magnitude: Magnitude
    method: str
    iterations: int
    support_calls: int
    forces: Matrix
    world_forces: Matrix
    wrenches: Matrix
    resultant: list[float]


class CompareRow(BaseModel):
    """A baseline's answer: its sigma, status, seconds, and error = sigma / ours - 1."""
    solver: Literal["clarabel", "osqp"]
    method: str
    status: str
    sigma: Num
    sigma_lower: Num
    seconds: float
    error: Num


class ForceOptimizationOut(MinForceOut):
    seconds: float
    compare: list[CompareRow] | None = None


class BatchSummary(BaseModel):
    count: int
    feasible: int
    statuses: dict[str, int]
    sigma_min: Num
    sigma_median: Num
    sigma_mean: Num
    sigma_max: Num
    iterations_mean: float


class BatchOut(BaseModel):
    """graspforce.MinForceBatch: per wrench sigma (null when infinite), sigma_lower, status,
    feasibility and iterations; forces (k, m, 4) if asked; the sampled wrenches when drawn."""
    norm: Norm
    magnitude: Magnitude
    method: str
    sigma: list[Num]
    sigma_lower: list[Num]
    status: list[str]
    feasible: list[bool]
    iterations: list[int]
    forces: list[Matrix] | None
    wrenches: Matrix | None
    summary: BatchSummary
    seconds: float


class QualityOut(BaseModel):
    """graspforce.GraspQuality: value bracketed by lower <= value <= upper."""
    force_closure: bool
    value: float
    lower: float
    upper: float
    direction: list[float]
    norm: Norm
    magnitude: Magnitude
    iterations: int
    support_calls: int


class ForceClosureOut(BaseModel):
    force_closure: bool
    quality: QualityOut | None


class RayShotOut(BaseModel):
    """graspforce.RayShot: z = t r with t <= t* <= t_upper, vertices Z_A(r) with weights and
    witnesses ([leaf index, leaf-local point or vertex index] per active leaf), the supporting
    normal and h_A(normal)."""
    hit: bool
    status: Literal["hit", "miss", "max_iter"]
    method: str
    r: list[float]
    t: Num
    t_upper: Num
    point: list[float]
    support_value: Num
    normal: list[float]
    vertices: Matrix
    weights: list[float]
    witnesses: list[list[list[int | list[float]]]]
    witness_rows: Matrix
    iterations: int
    support_calls: int
    singular_steps: int


class GrowthDistanceOut(BaseModel):
    """graspforce.GrowthDistanceResult: sigma in [sigma_lower, sigma_upper] (null when
    infinite), status, the contact points and the normal from a to b."""
    sigma: Num
    sigma_lower: Num
    sigma_upper: Num
    status: Literal["separated", "touching", "penetrating", "max_iter"]
    method: str
    iterations: int
    support_calls: int
    point_a: list[float]
    point_b: list[float]
    normal: list[float]


class Health(BaseModel):
    status: str


class Ready(BaseModel):
    status: str
    core: str
    threads: int


class ErrorOut(BaseModel):
    detail: str


# -- robots ------------------------------------------------------------------------------------------
Joints = Annotated[list[Coord], Field(min_length=1, max_length=256)]


class MotionIn(Model):
    """A motion sample at the scenario's configuration: joint velocities v and accelerations a
    (nv each; a floating base only)."""
    v: Joints | None = None
    a: Joints | None = None


class RobotForceIn(Model):
    """Minimal contact forces for a shipped scenario (Scenario.solve): its own load, or w_ext
    (a wrench about the reference point), or the load of a motion; optionally at another
    configuration q (nq numbers; the contacts follow their frames)."""
    model_config = ConfigDict(json_schema_extra={"examples": [{
        "norm": "L1", "magnitude": "normal", "method": "zc-ie", "eps": 1e-9}]})
    norm: Norm = "L1"
    magnitude: Magnitude = "normal"
    method: Method = "zc-ie"
    eps: Eps = 1e-9
    configuration: Joints | None = None
    w_ext: Wrench | None = None
    motion: MotionIn | None = None


class RobotSummary(BaseModel):
    name: str
    description: str
    robot: str
    floating_base: bool
    contacts: int


class RobotContactOut(BaseModel):
    name: str
    kind: str
    point: list[float]
    normal: list[float]
    mu: float
    mu_spin: float


class RobotOut(BaseModel):
    """A scenario: robot, configuration, reference point, load and contacts (world frame)."""
    name: str
    description: str
    robot: str
    floating_base: bool
    nq: int
    nv: int
    configuration: list[float]
    reference: list[float]
    external_wrench: list[float]
    contacts: list[RobotContactOut]


class RobotForcesOut(BaseModel):
    """graspforce.robots.RobotForces: the MinForce record, world forces and their points, joint
    torques, effort limits (null where none) and the joints over them."""
    status: str
    record: MinForceOut
    forces: Matrix
    points: Matrix
    torques: list[float]
    effort_limit: list[Num]
    over_limit: list[bool]
    exceeded: list[str]
