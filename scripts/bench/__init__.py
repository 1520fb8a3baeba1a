"""bench — pmc's benchmark and CI tools, one module per tool.

Run them from anywhere as `scripts/python -m bench.<module> [options]`
(scripts/python puts scripts/ on PYTHONPATH and runs the project's .venv):

    bench.cache       the material cache off vs on, cache-eval modes, the cache point threshold
    bench.cache_policy  --cache-policy keep-first vs priority in tables smaller than the automatic size
    bench.cache_position  --cache-keys uv vs uv+position on scenes with solid (position-driven) textures
    bench.cache_replay  the hits any replacement policy could get from a smaller table (lookup trace + replay)
    bench.cacheless   the cacheless path against a pmc built from before the cache existed
    bench.layered_bsdf  the layered BSDF's cost and the cache's speedup, against the pmc before it
    bench.materials   how much of the render time goes into material networks
    bench.material_peers  pmc's materials against Mitsuba 3's (scripts/setup-peers installs Mitsuba)
    bench.node_costs  what one node of each costly pattern family (noises, tiled shapes) costs
    bench.sampler     relMSE against spp: the Owen-scrambled Sobol sampler against random numbers
    bench.sweep       `pmc sweep` cache size / mip bias / equal-time convergence figures
    bench.trace       pmc against Embree's own pathtracer; pmc's query styles and streaming
    bench.waves       small frames against large ones at equal paths (several samples per wave)
    bench.ci_compare  the cache quality gate behind scripts/ci-compare

Each benchmark measures in round-robin rounds, prints its tables and rewrites
its own section of docs/BENCHMARKS.md (--doc FILE elsewhere, --doc - prints
only). What they share (machine description, rounds and medians, markdown
tables, section replacement, running pmc and reading its --stats JSON) is in
bench.common; bench/tests checks it (ctest runs it).
"""
