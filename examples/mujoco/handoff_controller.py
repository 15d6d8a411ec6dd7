"""The scripted controller of examples/mujoco/handoff.xml: FN(model, data) sets the four jaw
motors (N, positive = squeeze) from the time alone, so the rollout is deterministic.

- 0 to 0.3 s: gripper A squeezes 15 N per jaw; B's jaws are held open (-2 N against their stops);
- 0.3 to 0.5 s: B's jaws close with 2 N and touch the cylinder;
- 0.5 to 0.8 s: B's squeeze rises to 15 N (smoothstep);
- 0.8 to 1.3 s: A's squeeze falls to zero (smoothstep), then A opens (-2 N);
- to 1.6 s: B holds the cylinder alone.

Run: python -m grasp.mujoco handoff examples/mujoco/handoff.xml --object cylinder \\
         --controller examples/mujoco/handoff_controller.py:control --steps 1600 --every 10 ...
"""


def smoothstep(t, t0, t1, a, b):
    """a before t0, b after t1, the smoothstep between."""
    s = min(max((t - t0) / (t1 - t0), 0.0), 1.0)
    return a + (b - a) * s * s * (3.0 - 2.0 * s)


def squeezes(t):
    """(gripper A's, gripper B's) motor force per jaw at time t, N."""
    a = 15.0 if t < 0.8 else (smoothstep(t, 0.8, 1.3, 15.0, 0.0) if t < 1.3 else -2.0)
    b = -2.0 if t < 0.3 else (2.0 if t < 0.5 else smoothstep(t, 0.5, 0.8, 2.0, 15.0))
    return a, b


def control(model, data):
    """Sets data.ctrl (actuators a1, a2, b1, b2) for data.time."""
    a, b = squeezes(data.time)
    data.ctrl[:] = [a, a, b, b]
