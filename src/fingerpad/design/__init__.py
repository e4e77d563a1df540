"""Designing textures: sweeps of texture dimensions on Dask, the design map, inverse design.

* :mod:`.spec`, :mod:`.axes` - a sweep: the ``predict`` study plus a ``[sweep]`` table;
* :mod:`.evaluate` - one point, reduced to the design-map numbers (runs in Dask workers);
* :mod:`.store` - the Zarr store, laid out once, filled chunk by chunk, resumable, checked and repaired;
* :mod:`.store_population` - its population bands (``fingerpad sweep --population``);
* :mod:`.engine` - the Dask client: LocalCluster or an existing scheduler;
* :mod:`.designmap` - the design map's data on two swept axes;
* :mod:`.inverse` - textures that meet a friction target, each checked by a direct prediction;
* :mod:`.inverse_design` - inverse design as one call (what ``fingerpad design`` runs).
"""
