"""Inverse design (issue 17, docs/inverse.md): from a target shape to servo placement and values.

* :mod:`.targets`: target files (node positions / poses, ``solve`` results, folds, surfaces, keyframes);
* :mod:`.tangent`: exact derivatives of the kinematic poses with respect to D;
* :mod:`.residuals`: residuals of a target frame and their Jacobians (with a rigid / similarity alignment);
* :mod:`.fit`: :class:`~.fit.Problem`, the values-only Gauss-Newton fit, the free field;
* :mod:`.search`: placement search (linearised stage, full fits, swaps; a mapper distributes candidates);
* :mod:`.hinges`: hinge lengths per region as extra unknowns;
* :mod:`.evaluate`: the answer as a scene, its errors under every model, the lattice polish;
* :mod:`.picture`: the answer over the target as a PNG.

Pure numpy / scipy (matplotlib for the picture only); process pools and Dask live in
``metamaterial_wb.parallel``.
"""

# local worker processes of the placement search: the command line's ``inverse --workers`` and the Fit to target
# panel's Workers box (one bound; here, without numpy, as the command line imports it to build its options)
WORKERS_RANGE = (1, 256)
