"""Benchmarks: generator tick times, solver comparisons."""
