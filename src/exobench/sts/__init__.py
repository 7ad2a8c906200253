"""Sit-to-stand kinematics, joint loads and thigh-link checks (seed 001_2ff8c70b525eac91)."""
