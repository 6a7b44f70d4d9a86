"""Shooting: GJK and ZC, point to set and point to cone (distance.py), and ray shooting with its
five procedures (ray_shoot.py), all run by the compiled core (core/shooting/)."""
