"""min_force's common call, compiled whole once a wrench set's start table is settled
(core/python/min_force_call.hpp), answers exactly as the general path of Grasp.min_force: every
field of the record, bit for bit, on feasible, infeasible and zero loads, in R^6 and in a
rank-deficient grasp's span, and it refuses what the general path refuses."""
import inspect
import pickle

import numpy as np
import pytest
from grasp_cases import random_grasp, random_wrench

import graspforce as gf
from graspforce._core import min_force_compiled
from graspforce.grasping import grasp as grasp_module

OBJECTIVES = [(norm, magnitude) for norm in ("L1", "Linf") for magnitude in ("normal", "full")]
FIELDS = ("feasible", "status", "sigma", "sigma_lower", "norm", "magnitude", "method",
          "iterations", "support_calls")
ARRAYS = ("forces", "world_forces", "wrenches", "resultant")


def general(grasp, w, norm, magnitude, method="zc-ie"):
    """The general path's answer: a tolerance of the default's value but not a float (nor the
    default object) skips the compiled call."""
    return grasp.min_force(w, norm, magnitude, method, eps=np.float64(grasp_module.EPS))


def assert_same_record(a, b, same_grasp=True):
    assert type(a) is type(b)
    for name in FIELDS:
        x, y = getattr(a, name), getattr(b, name)
        assert type(x) is type(y) and (x == y or (x != x and y != y)), name
    for name in ARRAYS:
        x, y = getattr(a, name), getattr(b, name)
        assert x.shape == y.shape and np.array_equal(x.view(np.int64), y.view(np.int64)), name
    assert (a.ray is None) == (b.ray is None)
    if a.ray is not None:
        assert a.ray[4] == b.ray[4] and a.ray[2] == b.ray[2]
        assert not same_grasp or (a.ray[0] is b.ray[0] and a.ray[5] is b.ray[5])
        assert a.shot.t == b.shot.t and a.shot.t_upper == b.shot.t_upper
        assert np.array_equal(a.shot.normal, b.shot.normal)
    assert repr(a) == repr(b)


def settle(grasp, w, norm, magnitude, method="zc-ie"):
    """Shots until the set's start table is settled and the compiled call is made."""
    for _ in range(3):
        grasp.min_force(w, norm, magnitude, method)
    assert (norm, magnitude, method) in grasp._compiled


@pytest.mark.parametrize("norm,magnitude", OBJECTIVES)
def test_compiled_call_answers_as_the_general_path(norm, magnitude):
    rng = np.random.default_rng(11)
    statuses = set()
    for m in (1, 2, 3, 4, 6):
        for _ in range(3):
            grasp = random_grasp(rng, m)
            settle(grasp, random_wrench(rng), norm, magnitude)
            loads = [random_wrench(rng) for _ in range(8)]
            loads += [np.zeros(6), -np.zeros(6), 1e3 * random_wrench(rng)]
            for w in loads:
                fast = grasp.min_force(w, norm, magnitude)
                assert fast.ray is None or fast.ray[1] is w
                assert_same_record(fast, general(grasp, w, norm, magnitude))
                statuses.add(fast.status)
    assert statuses == {"optimal", "infeasible"}


def test_rank_deficient_grasps_answer_in_their_span_and_beyond():
    # two point contacts: W spans R^5; loads in the span are shot there, others at R^6's set
    grasp = gf.Grasp([gf.Contact([0.0, -0.03, 0.0], [0.0, 1.0, 0.0], 0.5, 0.0),
                      gf.Contact([0.0, 0.03, 0.0], [0.0, -1.0, 0.0], 0.5, 0.0)])
    weight = np.array([0.0, 0.0, -2.0, 0.0, 0.0, 0.0])
    settle(grasp, weight, "L1", "normal")
    rng = np.random.default_rng(3)
    for w in (weight, 0.5 * weight, np.array([0.0, 0.0, -1.0, 0.01, 0.0, 0.0]),
              random_wrench(rng), random_wrench(rng)):
        assert_same_record(grasp.min_force(w), general(grasp, w, "L1", "normal"))


def test_other_methods_and_inputs_the_compiled_call_does_not_take():
    rng = np.random.default_rng(7)
    grasp = random_grasp(rng, 4, kinds=("soft",))
    w = random_wrench(rng)
    settle(grasp, w, "L1", "normal", "ie")
    assert_same_record(grasp.min_force(w, method="ie"), general(grasp, w, "L1", "normal", "ie"))
    # a list, integers, a strided view and a (6, 1) column go through the general path
    compiled = grasp._compiled[("L1", "normal", "ie")]
    strided = np.repeat(w, 2)[::2]
    for other in (w.tolist(), np.arange(1, 7), strided, w.reshape(6, 1)):
        assert min_force_compiled(compiled, other) is None
    for other in (w.tolist(), strided):
        assert_same_record(grasp.min_force(other, method="ie"),
                           general(grasp, np.array(w), "L1", "normal", "ie"))
    with pytest.raises(ValueError, match="w_ext"):
        grasp.min_force(np.full(6, np.nan), method="ie")
    with pytest.raises(ValueError, match="w_ext"):
        grasp.min_force(np.ones(5), method="ie")
    with pytest.raises(TypeError, match="min_force_call"):
        min_force_compiled(object(), w)


def test_the_common_call_takes_the_compiled_call():
    """The class's min_force (core/python/min_force_method.hpp) takes the compiled call for the
    default tolerances, given or not, by position or by keyword; other tolerances, arguments it
    does not match and their errors are the Python method's."""
    rng = np.random.default_rng(5)
    grasp = random_grasp(rng, 4, kinds=("soft",))
    w = random_wrench(rng)
    settle(grasp, w, "L1", "normal")
    key = ("L1", "normal", "zc-ie")
    compiled = grasp._compiled[key]
    a = grasp.min_force(w)
    # an object that is not a compiled call in its place: a call that takes it raises
    grasp._compiled[key] = object()
    try:
        for args, kwargs in (((), {}), (("L1", "normal", "zc-ie", 1e-9, 10000), {}),
                             ((), {"eps": float("1e-9"), "max_iter": int("10000")}),
                             ((), {"method": "zc-ie", "norm": "L1"})):
            with pytest.raises(TypeError, match="min_force_call"):
                grasp.min_force(w, *args, **kwargs)
        b = grasp.min_force(w, eps=np.float64(1e-9))
        c = grasp.min_force(w, eps=1e-8)
        d = grasp.min_force(w_ext=w)
    finally:
        grasp._compiled[key] = compiled
    assert_same_record(a, b)
    assert_same_record(a, d)
    assert c.status == "optimal" and abs(c.sigma - a.sigma) <= 1e-8 * a.sigma
    with pytest.raises(TypeError, match="unexpected keyword argument 'tol'"):
        grasp.min_force(w, tol=1e-9)
    with pytest.raises(TypeError, match="unexpected keyword argument"):
        grasp.min_force(w, **{f"x{i}": i for i in range(20)})
    with pytest.raises(TypeError, match="multiple values for argument 'norm'"):
        grasp.min_force(w, "L1", norm="L1")
    with pytest.raises(TypeError, match="w_ext"):
        grasp.min_force()
    with pytest.raises(ValueError, match="norm"):
        grasp.min_force(w, ["L1"])
    # the Python method's name, signature and docstring
    assert gf.Grasp.min_force.__name__ == "min_force"
    assert str(inspect.signature(gf.Grasp.min_force)) == (
        "(self, /, w_ext, norm='L1', magnitude='normal', method='zc-ie', eps=1e-09, "
        "max_iter=10000)")
    assert gf.Grasp.min_force.__doc__.startswith("Contact forces in the friction cones")


def test_reset_and_pickling_drop_the_compiled_calls():
    rng = np.random.default_rng(9)
    grasp = random_grasp(rng, 3, kinds=("soft",))
    w = random_wrench(rng)
    settle(grasp, w, "L1", "normal")
    copy = pickle.loads(pickle.dumps(grasp))
    assert copy._compiled == {}
    assert_same_record(copy.min_force(w), gf.Grasp(grasp.contacts).min_force(w), False)
    grasp.reset_start_tables()
    assert grasp._compiled == {}
    # a reset grasp answers as a new one (its first shot has no table)
    assert_same_record(grasp.min_force(w), gf.Grasp(grasp.contacts).min_force(w), False)
