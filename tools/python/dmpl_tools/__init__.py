"""dmpl's Python tools: launcher, experiment runner, metrics, reports, sweeps, benchmarks."""
