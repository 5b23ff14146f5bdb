"""The QP back-ends of the solver benchmark: its registry (the project's back-ends plus
CasADi's Opti layer) and their settings per tolerance level."""
