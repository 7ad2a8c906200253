"""Rule phantom_qc_figure: what the screening repaired or left as gaps, and the strides kept."""

from matplotlib import pyplot as plt

from exobench import figures, runner, tables
from exobench.phantom.report import plots


def stage(smk, provenance):
    trials = smk.params.trials
    checks = {t: tables.read_table(p).data for t, p in zip(trials, smk.input.qc, strict=True)}
    strides = {t: tables.read_table(p).data for t, p in zip(trials, smk.input.strides, strict=True)}
    fig = plots.quality_control(checks, strides)
    figures.save(fig, smk.output.png, smk.output.pdf)
    caption = plots.quality_control_caption(checks, strides, int(smk.params.max_gap_frames))
    figures.write_caption(smk.output.caption, *caption)
    plt.close(fig)


runner.run(snakemake, stage)
