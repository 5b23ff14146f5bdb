"""The inverse-dynamics QP of torque control in the solver benchmark: the problem set taken
along torque-mode walks in MuJoCo, its timed solves, each back-end in the loop, the report."""
