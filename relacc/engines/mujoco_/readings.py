"""The differences in MuJoCo's algorithms relacc knows as readings to re-run: none (MuJoCo's known bugs in reading a
file, relacc's reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`; its known algorithmic
differences are explained by :func:`relacc.validation.robots.mujoco_causes.mujoco_cause`)."""

ENGINE_READINGS = ()
"""No known difference in MuJoCo's algorithms to re-run."""
