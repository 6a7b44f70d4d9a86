"""Geometry: convex sets (sets.py), the support programs they compile to and the kernel's layout
(_kernel.py), and a set's start table, an inner polytope of its support points (_start_table.py)."""
