"""Growth distance (section 4) between two posed convex sets (growth.py)."""
