"""Rule phantom_qc_figure: what the screening repaired or left as gaps, and the strides kept;
trials by spring rate, channels under the lab's own labels."""

from exobench import figures, tables
from exobench.phantom.recordings import c3d
from exobench.phantom.report import plots
from exobench.plumbing import runner


def stage(smk, provenance):
    trials = smk.params.trials
    checks = {t: tables.read_table(p).data for t, p in zip(trials, smk.input.qc, strict=True)}
    strides = {t: tables.read_table(p).data for t, p in zip(trials, smk.input.strides, strict=True)}
    manifest = c3d.read_manifest(smk.input.manifest).set_index("trial")
    springs = manifest.loc[trials, "spring_stiffness_N_per_m"].to_dict()
    labels = smk.params.labels
    drawn = (
        plots.quality_control(checks, strides, springs, labels),
        plots.quality_control_caption(
            checks, strides, int(smk.params.max_gap_frames), springs, labels
        ),
    )
    figures.publish(smk.output, smk.params.figures, {"qc": drawn})


runner.run(snakemake, stage)
