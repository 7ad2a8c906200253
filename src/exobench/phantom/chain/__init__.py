"""The analysis chain: filtering, strides, angles, inverse dynamics, power and metrics."""
