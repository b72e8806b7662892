"""What a matrix does near and away from its rank-deficiency locus.

- :mod:`.min_inf_norm`: minimum infinity-norm solutions of A x = y (Ha and
  Lee's algorithm, the linear program); :mod:`.cadzow`: Cadzow's algorithm;
- :mod:`.discontinuity`: the discontinuity index and the mixing ratio;
- :mod:`.manipulability`: the manipulability ellipsoid and polytope;
- :mod:`.nearest`: the nearest component of a locus and the distance to it;
- :mod:`.path`: joint rates along a task-space path;
- :mod:`.figures`: matplotlib figures of the above (each takes ``ax=``).
"""
