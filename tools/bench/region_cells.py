"""The bench_region cells the A/B scripts (region_ab.py, region_ab_ir.py)
compare by default: whole region, 10x wider and 4e-4 boundary zoom of the
cubic Bezier (P1), fig8 P3 and the degree-9 Bezier (P4)."""
DEFAULT_CELLS = [
    "P1 whole region 10 1024", "P1 10x wider 10 1024", "P1 4e-4 zoom 10 1024",
    "P3 whole region 10 1024", "P3 10x wider 16 512", "P3 4e-4 zoom 10 1024",
    "P4 whole region 10 1024", "P4 10x wider 10 1024", "P4 4e-4 zoom 10 512", "P4 4e-4 zoom 16 1024",
]
