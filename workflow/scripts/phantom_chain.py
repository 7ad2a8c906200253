"""Rule phantom_chain: one trial's acquisition, filtering, angles, strides, inverse dynamics and
power partition, each stage's table to its own Parquet file."""

from pathlib import Path

from exobench import tables
from exobench.errors import InputError
from exobench.phantom import reference
from exobench.phantom.chain import filtering, trial
from exobench.phantom.recordings import c3d, qc
from exobench.phantom.rig import Rig
from exobench.plumbing import provenance, runner

FLAGS = ("analog_gap",)  # flags whose unit the table's name suffixes do not give


def stage(smk, record):
    name = smk.wildcards.trial
    manifest = c3d.read_manifest(Path(smk.input.manifest))
    rows = manifest[manifest["trial"] == name]
    if rows.empty:
        raise InputError(smk.input.manifest, "trial", f"a row for trial '{name}'")
    settings = {
        "chain": smk.params.chain,
        "stride_time_s": smk.params.stride_time_s,
        "min_spring_force_N": smk.params.min_spring_force_N,
    }
    swing = reference.swing_fraction(tables.read_table(smk.input.cycle).data)
    rig = Rig.from_config(smk.params.rig)
    out = trial.run(Path(smk.input.c3d), rows.iloc[0], settings, swing, rig, smk.params.labels)
    runner.LOG.info(
        "%s (strides by %s)",
        qc.summary_line(name, out.qc, out.strides),
        out.strides["segmentation"].iloc[0],
    )
    filtered_markers, filtered_analog = filtering.split(out.filtered)
    flags = {c: "1" for c in FLAGS if c in filtered_analog.columns}
    o = smk.output
    for path, table, units in (
        (o.markers, out.markers, None),
        (o.analog, out.analog, None),
        (o.events, out.events, qc.TEXT_UNITS),
        (o.filtered_markers, filtered_markers, None),
        (o.filtered_analog, filtered_analog, flags),
        (o.angles, out.angles, None),
        (o.strides, out.strides, None),
        (o.qc, out.qc, qc.QC_UNITS),
        (o.moments, out.moments, None),
        (o.kinetics, out.kinetics, None),
    ):
        tables.write_table(path, table, record, units)


runner.run(snakemake, stage)
