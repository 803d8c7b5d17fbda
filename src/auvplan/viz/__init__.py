"""Figures: static matplotlib plots (``plots``) and the offline plotly report (``report``)."""
