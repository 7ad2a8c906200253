"""Rule phantom_acquire_trial: every C3D trial, checked against the contract (docs/rig.md),
screened for glitches and resampled to the analysis rates, to Parquet."""

from pathlib import Path

from exobench.phantom.recordings import acquire
from exobench.plumbing import provenance, runner


def stage(smk, record):
    out = smk.output
    settings = {
        "labels": smk.params.labels,
        "stride_time_s": float(smk.params.stride_time_s),
        "chain": {
            "glitches": smk.params.glitches,
            "max_gap_frames": smk.params.max_gap_frames,
            "unit_slips": smk.params.unit_slips,
            "sync_threshold_V": smk.params.sync_threshold_V,
            "read_timeout_s": smk.params.read_timeout_s,
        },
        "rig": smk.params.rig,
    }
    for trial, c3d, markers, analog, events in zip(
        smk.params.trials, smk.input.c3d, out.markers, out.analog, out.events, strict=True
    ):
        row = acquire.acquire(
            Path(smk.input.manifest),
            trial,
            {"markers": markers, "analog": analog, "events": events},
            provenance.restrict(record, [smk.input.manifest, c3d], smk.config),
            settings,
        )
        runner.LOG.info("acquired %s", row)


runner.run(snakemake, stage)
