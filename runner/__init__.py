"""WireNet's case runner: case files (TOML) -> generator -> deck -> LIGGGHTS -> analysis -> report.

`./wirenet run` enters at runner.__main__; the analysis of the dumps lives in the package
`postprocess`, which this package calls and which never calls back.
"""
