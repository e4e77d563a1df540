"""The explorer's views (Panel): the single-texture view, the comparison, the design map."""
