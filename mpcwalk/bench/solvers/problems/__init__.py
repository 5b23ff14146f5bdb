"""The walking QPs of the solver benchmark: problem families, walks, and the problems
sampled from them."""
