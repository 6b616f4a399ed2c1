"""Which work folder holds a table's runs: its own, or sgdo-main for the SGDO-SLAM tables that read
the same runs. Shared by workflow/Snakefile and scripts/regen-checkpoint.py."""

SGDO_MAIN = ["sgdo-table1", "sgdo-table2", "sgdo-table3", "sgdo-table4", "sgdo-table7"]


def work_of(table):
    """The work folder (under the workflow's work) of `table`."""
    return "sgdo-main" if table in SGDO_MAIN else table


def tables_of(tables):
    """work folder -> its tables, in the order given (the first one's seed jobs fill it)."""
    out = {}
    for t in tables:
        out.setdefault(work_of(t), []).append(t)
    return out
