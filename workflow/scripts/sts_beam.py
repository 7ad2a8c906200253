"""Rule sts_beam: closed-form thigh-link checks and the comparison with the study's FEA."""

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import strength


def stage(smk, provenance):
    cfg = smk.params
    loads = tables.read_table(smk.input.loads).data
    report = strength.check(
        cfg["thigh_link"],
        float(cfg["design_load_N"]),
        float(cfg["l_BC_mm"]),
        (loads["thigh_bending_moment_Nm"], loads["thigh_axial_force_N"]),
        strength.read_reported(smk.input.reported),
    )
    runner.LOG.info("thigh link: %s", report["explanation"])
    atomic.write_json(smk.output[0], {**report, "provenance": provenance})


runner.run(snakemake, stage)
