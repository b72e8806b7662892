"""Sweeps: many independent locus computations, over robot collections and design spaces.

- :mod:`.spec`: the sweep specification (TOML, read as data) and its validation;
- :mod:`.cases`: the cases it expands to, with the hashes that make a sweep resumable;
- :mod:`.task`: one case computed under its time and memory limits (what a worker runs);
- :mod:`.execute`: where the cases run: in this process or on Dask distributed;
- :mod:`.summary`: summary.csv, summary.md and the figure, from the case records.

``rankloci sweep SPEC.toml -o DIR`` (:mod:`rankloci.cli.sweep`) ties them together and is
the only part that writes files.
"""

__all__ = ["spec", "cases", "task", "execute", "summary"]
