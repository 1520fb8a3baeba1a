"""farm — renders one pmc frame in chunks on Dask distributed and merges them.

scripts/farm-render runs `python -m farm` (farm/__main__.py). The frame is
split into chunks (farm/split.py: sample ranges, or tiles), each chunk is one
`pmc render --samples A:B` / `--crop` process run by a Dask task
(farm/chunk.py), and `pmc merge` adds the parts at the end (farm/run.py).
"""
