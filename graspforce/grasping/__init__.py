"""Grasping: contacts (contact.py), their wrench sets (wrench_space.py), the grasp and its minimum
contact forces (grasp.py), force closure and quality (quality.py), and the generic solvers'
answers to the same problems (baselines/)."""
