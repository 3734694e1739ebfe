"""What is computed from runs, each run asked of an engine."""
