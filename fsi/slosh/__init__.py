"""Slosh analysis: free-decay fits, the SP-106 spring-mass equivalent, modes, tank response, the limp surface, lateral compliance."""
