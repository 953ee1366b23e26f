arm_name(a1, 'left arm).
arm_name(a2, 'right arm').
