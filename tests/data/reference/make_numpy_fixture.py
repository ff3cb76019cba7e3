#!/usr/bin/python3
"""Writes numpy_fixture.npz: arrays saved by numpy itself (np.savez_compressed, which writes zip64
extra fields into its local headers), so that the C++ NPZ reader is checked against numpy's own
output even where python3/numpy are not installed. Values are simple closed forms that
tests/unit/reference/npz_test.cpp recomputes. Run from this folder: /usr/bin/python3 make_numpy_fixture.py
"""
import numpy as np

T, J = 5, 3
k = np.arange(T, dtype=np.float64)
np.savez_compressed(
    "numpy_fixture.npz",
    fps=np.array([50.0]),
    joint_names=np.array(["hip", "knee", "ankle_\u00e4"]),
    joint_pos=np.asfortranarray(0.1 * k[:, None] + np.arange(J)[None, :]),  # Fortran order on disk
    root_pos_w=np.stack([0.01 * k, 0 * k, 0.8 + 0 * k], axis=1),
    root_quat_w=np.tile(np.array([1.0, 0.0, 0.0, 0.0]), (T, 1)),
    contacts=np.array([[True, True], [True, False], [True, False], [False, True], [True, True]]),
    counts=np.arange(6, dtype=np.int32).reshape(2, 3),
    big=np.array([-(2**40), 2**40], dtype=np.int64),
    small=np.array([1.5, -2.25], dtype=np.float32),
    bytes_=np.array([0, 255], dtype=np.uint8),
    scalar=np.float64(3.5),
)
