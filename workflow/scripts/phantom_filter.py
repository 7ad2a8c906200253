"""Rule phantom_filter: gap fill, 6 Hz zero-phase Butterworth, markers to 1000 Hz."""

from exobench import phantom, runner, tables
from exobench.phantom import filtering


def stage(smk, provenance):
    chain = phantom.settings(smk.config)["chain"]
    markers = tables.read_table(smk.input.markers).data
    analog = tables.read_table(smk.input.analog).data
    filtered = filtering.filter_trial(markers, analog, chain, smk.input.markers)
    tables.write_table(smk.output[0], filtered, provenance)


runner.run(snakemake, stage)
