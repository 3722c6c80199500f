"""Benchmark harnesses (above ``core`` and ``fe``, below the command line; nothing in ``core`` imports them).

* :mod:`.fidelity`: the fidelity ladder (every model on the standard scenes, error against run time);
* :mod:`.reference`: the converged lattice reference (hinges of n elements, Richardson extrapolation) and
  the error bars it puts on every figure;
* :mod:`.plots`: the work-precision diagrams;
* :mod:`.fe_study`: the CalculiX studies (hinge stiffness, bending curves, aspect ratios, the 3 x 3 patch).
"""
