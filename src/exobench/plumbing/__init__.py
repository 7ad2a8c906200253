"""The workflow's plumbing: running a rule's stage, the console, code params, config checks, the
results lock, the twins' stamps, provenance and the benchmark command; no science here."""
