"""Rule sts_fe: the thigh link by finite elements (plane stress, quadratic triangles) under the
study's load cases, its mesh convergence, the load-introduction hypotheses, the beam formulas
against the field, the study's fully fixed support beside the configured one, and the section
search."""

import pandas as pd

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import fea, sections, strength


def stage(smk, provenance):
    cfg = smk.params
    reported = strength.read_reported(smk.input.reported)
    link = fea.link_from_config(cfg["thigh_link"], float(cfg["l_BC_mm"]), cfg["design_load_N"])
    report, (nodes, triangles) = fea.analyse(link, cfg["fe"], reported)
    runner.LOG.info("finest mesh: %s", report["finest"])
    report["fixed_support"] = fea.fixed_support(link, cfg["fe"])
    runner.LOG.info("fully fixed face: %s", report["fixed_support"]["table"])
    report["levers"] = fea.levers(link)
    factor = sections.bearing_factor(link, report)
    sizes = [float(s) for s in cfg["fe"]["element_mm"][-2:]]
    rows, screened = sections.search(
        cfg["sections"], link, factor, reported, (sizes[0], sizes[0] / cfg["fe"]["hole_refinement"])
    )
    report["sections"] = {
        "screened": screened,
        "bearing_factor": factor,
        "element_mm": sizes[0],
        "ranges": {k: cfg["sections"][k] for k in ("depth_mm", "thickness_mm", "pin_diameter_mm")},
        "materials": cfg["sections"]["materials"],
        "tolerance_pct": cfg["sections"]["tolerance_pct"],
        "study_material": cfg["sections"]["study_material"],
        "targets": {
            "tip_deflection_mm": sections.midpoint(reported["tip_deflection_mm"]),
            "compression_peak_MPa": sections.midpoint(reported["compression_peak_MPa"]),
        },
        "implied": sections.implied(
            reported, report["levers"]["eq5_lever_mm"], link.plate.E_MPa, link.section.depth_mm
        ),
        "implied_configured_lever": sections.implied(
            reported,
            report["levers"]["configured_lever_mm"],
            link.plate.E_MPa,
            link.section.depth_mm,
        ),
    }
    runner.LOG.info("section search: %s", rows)
    tables.write_csv(smk.output.sections, pd.DataFrame(rows), provenance)
    tables.write_table(smk.output.field, pd.DataFrame(nodes), provenance)
    tables.write_table(
        smk.output.mesh, pd.DataFrame(triangles), provenance, dict.fromkeys(triangles, "1")
    )
    atomic.write_json(smk.output.report, {**report, "seed_fea": reported, "provenance": provenance})


runner.run(snakemake, stage)
