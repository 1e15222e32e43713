"""Evaluation: the synthetic dataset, real-recording loaders, baselines, metrics, the report."""
