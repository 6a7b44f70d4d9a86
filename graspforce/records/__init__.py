"""Records: what a computation returns (results.py), each with the bounds that certify it, and the
layout of the packed arrays they are read from (_packed.py, _forces.py). They import nothing of
graspforce but the compiled core."""
