"""Data of openEMSS installed with it (found as ``openemss.examples``): the folder's files, not code."""
