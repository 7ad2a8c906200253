"""Rule phantom_strides: one row per programmed stride with inclusion and reason (per trial)."""

from pathlib import Path

from exobench import tables
from exobench.phantom import reference
from exobench.phantom.chain import segmentation
from exobench.phantom.recordings import c3d, qc
from exobench.plumbing import provenance, runner


def stage(smk, record):
    manifest = c3d.read_manifest(Path(smk.input.manifest)).set_index("trial")
    cycle = tables.read_table(smk.input.cycle).data
    swing_fraction = reference.swing_fraction(cycle)
    inputs = zip(
        smk.params.trials,
        smk.input.filtered,
        smk.input.angles,
        smk.input.events,
        smk.output.strides,
        smk.output.qc,
        strict=True,
    )
    for trial, filtered, angles, events, out, qc_out in inputs:
        table = segmentation.segment(
            tables.read_table(filtered).data,
            tables.read_table(angles).data,
            int(manifest.loc[trial, "ramp_strides"]),
            swing_fraction,
            smk.params.chain,
            float(smk.params.min_spring_force_N),
            f"trial {trial} ({Path(smk.input.manifest).parent / manifest.loc[trial, 'file']})",
        )
        checked = qc.qc_table(trial, tables.read_table(events).data, table)
        runner.LOG.info(
            "%s (strides by %s)",
            qc.summary_line(trial, checked, table),
            table["segmentation"].iloc[0],
        )
        used = [smk.input.manifest, smk.input.cycle, filtered, angles]
        tables.write_table(out, table, provenance.restrict(record, used, smk.config))
        tables.write_table(
            qc_out, checked, provenance.restrict(record, [*used, events], smk.config), qc.QC_UNITS
        )


runner.run(snakemake, stage)
