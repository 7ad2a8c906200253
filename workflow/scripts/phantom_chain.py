"""Rule phantom_chain: one trial's acquisition, filtering, angles, strides, inverse dynamics and
power partition, each stage's table to its own Parquet file."""

from pathlib import Path

from exobench import tables
from exobench.errors import InputError
from exobench.phantom import reference
from exobench.phantom.chain import angles, filtering, kinetics, trial
from exobench.phantom.recordings import c3d, qc
from exobench.phantom.rig import Rig
from exobench.plumbing import runner

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
    # per-sample tables in float32 (their clock in float64), each without an earlier stage's
    # columns; the strides and QC tables as they are
    for path, table, units, single in (
        (o.markers, out.markers, None, True),
        (o.analog, out.analog, None, True),
        (o.events, out.events, qc.TEXT_UNITS, False),
        (o.filtered_markers, filtered_markers, None, True),
        (o.filtered_analog, filtered_analog, flags, True),
        (o.angles, out.angles[angles.OWN_COLUMNS], None, True),
        (o.strides, out.strides, None, False),
        (o.qc, out.qc, qc.QC_UNITS, False),
        (o.moments, out.moments, None, True),
        (o.kinetics, out.kinetics[kinetics.OWN_COLUMNS], None, True),
    ):
        tables.write_table(path, table, record, units, single)


runner.run(snakemake, stage)
