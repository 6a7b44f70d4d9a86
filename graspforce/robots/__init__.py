"""graspforce.robots: multi-contact scenarios on robot models (Pinocchio + example-robot-data).

    scenario = gf.robots.load_scenario("talos_double_support")   # or a path to a TOML file
    answer = scenario.solve(norm="L1", magnitude="normal")
    answer.record, answer.forces, answer.torques, answer.exceeded
    scenario.plot("talos.png")

Needs the `robots` extra (pin, example-robot-data, matplotlib); the contract is docs/robots.md.
"""
from .loading import build, list_scenarios, load_scenario, scenario_path
from .models import ROBOTS, load_model
from .scenario import Scenario
from .solution import RobotForces

__all__ = ["ROBOTS", "RobotForces", "Scenario", "build", "list_scenarios", "load_model",
           "load_scenario", "scenario_path"]
