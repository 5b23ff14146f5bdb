"""The solver benchmark beside its peers: the MPC tick against the qpmpc peer and the closed
form, the walking QPs as a qpbenchmark test set and qpbenchmark's own run on it."""
