"""An FK character made like a real rig (tests/python/test_rigs.py, tests/blender/test_rig_bones.py):
eleven rectangular pieces whose limbs and tail overlap the torso and each other in the rest pose,
and two poses given as each joint's turn in degrees (counter-clockwise, children after parents)."""

# piece: (rectangle x0, y0, width, height, parent, pin); the torso is the root and stays still
RIG = {
    "torso": ((-1.5, -2.5, 3.0, 4.5), None, None),
    "head": ((-0.8, 1.7, 1.6, 1.6), "torso", (0.0, 1.9)),
    "upper_r": ((0.9, -0.5, 0.6, 2.2), "torso", (1.2, 1.4)),      # lies over the torso
    "fore_r": ((0.9, -2.3, 0.6, 2.0), "upper_r", (1.2, -0.4)),
    "hand_r": ((0.85, -3.0, 0.7, 0.9), "fore_r", (1.2, -2.2)),    # over the torso's corner too
    "upper_l": ((-1.5, -0.5, 0.6, 2.2), "torso", (-1.2, 1.4)),
    "fore_l": ((-1.5, -2.3, 0.6, 2.0), "upper_l", (-1.2, -0.4)),
    "hand_l": ((-1.55, -3.0, 0.7, 0.9), "fore_l", (-1.2, -2.2)),
    "tail_1": ((-0.3, -3.2, 0.6, 1.2), "torso", (0.0, -2.3)),
    "tail_2": ((-0.3, -4.2, 0.6, 1.2), "tail_1", (0.0, -3.1)),
    "tail_3": ((-0.3, -5.2, 0.6, 1.2), "tail_2", (0.0, -4.1)),
}
NAMES = list(RIG)
POSES = {
    "limbs_out": dict(head=20, upper_r=70, fore_r=60, hand_r=30, upper_l=-50, fore_l=-80, hand_l=40,
                      tail_1=25, tail_2=30, tail_3=35),
    "hand_crosses_body": dict(head=-15, upper_r=-100, fore_r=-70, hand_r=-20, upper_l=30, fore_l=45,
                              hand_l=-35, tail_1=-40, tail_2=20, tail_3=-25),
}
