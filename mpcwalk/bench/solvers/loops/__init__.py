"""Each QP back-end as the MPC's solver in a closed loop, on the LIPM and in MuJoCo."""
