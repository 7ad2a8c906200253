"""Rule phantom_filter: gap fill, 6 Hz zero-phase Butterworth, markers to 1000 Hz (per trial)."""

from exobench import provenance, runner, tables
from exobench.phantom import filtering


def stage(smk, record):
    for markers_path, analog_path, out in zip(
        smk.input.markers, smk.input.analog, smk.output.filtered, strict=True
    ):
        markers = tables.read_table(markers_path).data
        analog = tables.read_table(analog_path).data
        filtered = filtering.filter_trial(markers, analog, smk.params.chain, markers_path)
        tables.write_table(
            out, filtered, provenance.restrict(record, [markers_path, analog_path], smk.config)
        )


runner.run(snakemake, stage)
