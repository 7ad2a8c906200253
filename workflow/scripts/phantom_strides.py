"""Rule phantom_strides: one row per programmed stride with inclusion and reason."""

from pathlib import Path

from exobench import phantom, runner, tables
from exobench.phantom import c3d, segmentation


def stage(smk, provenance):
    cfg = phantom.settings(smk.config)
    manifest = c3d.read_manifest(Path(smk.input.manifest))
    trial = smk.wildcards.trial
    row = manifest.set_index("trial").loc[trial]
    cycle = tables.read_table(smk.input.cycle).data
    swing_fraction = float(cycle["gait_cycle_pct"][cycle["knee_flexion_deg"].idxmax()]) / 100.0
    table = segmentation.segment(
        tables.read_table(smk.input.filtered).data,
        tables.read_table(smk.input.angles).data,
        int(row["ramp_strides"]),
        swing_fraction,
        cfg["chain"],
        float(cfg["protocol"]["min_spring_force_N"]),
        f"trial {trial} ({Path(smk.input.manifest).parent / row['file']})",
    )
    counts = table["exclusion_reason"].value_counts().to_dict()
    runner.LOG.info(
        "%s: %d strides by %s; %s",
        trial,
        len(table),
        table["segmentation"].iloc[0],
        counts,
    )
    tables.write_table(smk.output[0], table, provenance)


runner.run(snakemake, stage)
