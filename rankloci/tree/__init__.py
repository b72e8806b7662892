"""The branch tree of a locus computation.

- :mod:`~rankloci.tree.branch`: a branch, the set cut out by polynomial
  conditions, and how its conditions are solved;
- :mod:`~rankloci.tree.sampler`: real points of a branch;
- :mod:`~rankloci.tree.probe`: numeric evaluation of polynomial matrices at
  those points (rank, vanishing);
- :mod:`~rankloci.tree.context`: one computation's tree, leaves and notes;
- :mod:`~rankloci.tree.cover`: the children of a branch on a new condition;
- :mod:`~rankloci.tree.prune`: whether a branch lies inside a component found;
- :mod:`~rankloci.tree.blocks`: which square block of a matrix a branch is
  split on, or its null vectors are built from.
"""
