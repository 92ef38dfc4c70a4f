//! Scenes: what to simulate and with which parameters.
