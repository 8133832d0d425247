"""relacc's recorded benchmark runs (JSON), installed as the package data ``relacc.recorded``.

The report's throughput section reads them through :func:`relacc.fixtures.shipped.recorded_dir`;
this directory holds no code.
"""
