"""The rig's model for the discrepancy engine: effects, terms, assumptions, observations."""
