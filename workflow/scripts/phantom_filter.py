"""Rule phantom_filter: gap fill, 6 Hz zero-phase Butterworth, markers to 1000 Hz (per trial)."""

from exobench import tables
from exobench.phantom.chain import filtering
from exobench.plumbing import provenance, runner

FLAGS = ("analog_gap",)  # flags whose unit the table's name suffixes do not give


def stage(smk, record):
    outputs = zip(
        smk.input.markers, smk.input.analog, smk.output.markers, smk.output.analog, strict=True
    )
    for markers_path, analog_path, markers_out, analog_out in outputs:
        markers = tables.read_table(markers_path).data
        analog = tables.read_table(analog_path).data
        filtered = filtering.filter_trial(markers, analog, smk.params.chain, markers_path)
        used = provenance.restrict(record, [markers_path, analog_path], smk.config)
        for out, part in zip((markers_out, analog_out), filtering.split(filtered), strict=True):
            tables.write_table(out, part, used, {c: "1" for c in FLAGS if c in part.columns})


runner.run(snakemake, stage)
