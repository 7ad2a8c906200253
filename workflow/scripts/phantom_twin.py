"""Rule phantom_twin: the digital twin writes the phantom recordings (docs/rig.md §1) and truth."""

import json
from pathlib import Path

from exobench.phantom import reference
from exobench.phantom.rig import Rig
from exobench.phantom.twin import twin
from exobench.plumbing import runner


def stage(smk, provenance):
    cfg = runner.settings(smk)
    cycle = reference.read_mean_cycle(smk.input.cycle)["knee_flexion_deg"].to_numpy()
    fitted = json.loads(Path(smk.input.fit).read_text())["parameters"]
    trials = twin.simulate_trials(cycle, Rig.from_config(cfg["rig"]), cfg, fitted)
    folder = Path(smk.output.manifest).parent
    names = twin.write_recordings(trials, folder, provenance, int(cfg["protocol"]["ramp_strides"]))
    runner.LOG.info("wrote %d trials to %s", len(names), folder)


runner.run(snakemake, stage)
