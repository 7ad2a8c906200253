"""Rule emulator_twin: the emulator's digital twin writes docs/rig.md §3 recordings."""

from pathlib import Path

from exobench.emulator.twin import twin
from exobench.plumbing import runner


def stage(smk, provenance):
    recordings = twin.run(runner.settings(smk), int(smk.params.seed))
    for rec in recordings:
        runner.LOG.info(
            "%s: %d heel strikes, true energy %.3f J per step",
            rec.name,
            len(rec.truth["heel_strikes_s"]),
            sum(rec.truth["true_energy_per_step_J"])
            / max(len(rec.truth["true_energy_per_step_J"]), 1),
        )
    twin.write_recordings(recordings, Path(smk.output.manifest).parent)


runner.run(snakemake, stage)
