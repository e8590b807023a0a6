"""results.csv's measured columns: times and where they were taken, which differ between runs
and machines (docs/outputs.md). Every other column is computed and equal between runs of the
same study, whether run whole, resumed after a kill or merged from shards. The C++ list
(study/result_columns.h measuredResultColumns) is checked against this one by the test suite."""

MEASURED_COLUMNS = ("ns_per_px", "precompute_ms", "timing_backend", "ns_per_px_p25",
                    "ns_per_px_p75", "timing_repeats", "timing_fragments", "timing_case")


def without_measured(row):
    """A results.csv row (a dict) without its measured columns, as a sorted tuple."""
    return tuple(sorted((k, v) for k, v in row.items() if k not in MEASURED_COLUMNS))
