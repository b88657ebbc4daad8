"""Synthesis: from requirements to the best stack, over the whole design space.

Layering (above :mod:`springcad.design`, below the CLI):

- :mod:`~springcad.synthesis.requirements`: the requirements TOML schema;
- :mod:`~springcad.synthesis.candidates`: enumeration (a stable integer id per stack);
- :mod:`~springcad.synthesis.screening`: the closed-form single-disk design on arrays;
- :mod:`~springcad.synthesis.evaluate`: a batch of stacks -> a table (constraints with numbers);
- :mod:`~springcad.synthesis.ranking`: feasible stacks by objective, why families fail;
- :mod:`~springcad.synthesis.store`: Parquet part files per batch (resumable);
- :mod:`~springcad.synthesis.runner`: Dask execution with progress;
- :mod:`~springcad.synthesis.finalists`: full design, FEA of the finalists, the winner's job;
- :mod:`~springcad.synthesis.explore`: the design-space map (paper Fig. 8) and Pareto fronts.

The store is the one module here that writes files: it owns the resumable run folder.
"""
