"""In Jupyter the progress bar is tqdm's notebook widget (the `notebook`
extra installs ipywidgets for it), not text lines with `IProgress not
found`: a notebook run by nbclient in a real kernel shows the widget, and the
atlas's result, with no warning."""
import nbclient
import nbformat

from conftest import MULTI

CELL = f"""import vibroatlas as va
t = va.atlas({str(MULTI)!r}, x=("omega", 0.1, 3.05, 40), y=("delta", 0.05, 2.0, 20), sweep="up", threads=2)
print("cells", t["up"]["label_code_M1"].size)
"""


def test_the_progress_bar_in_a_notebook_is_a_widget(tmp_path):
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(CELL)]
    nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = nb.cells[0].outputs
    widgets = [o for o in outputs if o.output_type == "display_data"
               and "application/vnd.jupyter.widget-view+json" in o.data]
    streams = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert len(widgets) == 1, f"expected one progress widget, got outputs {outputs}"
    assert "IProgress not found" not in streams and "TqdmWarning" not in streams, streams
    assert "cells 800" in streams
