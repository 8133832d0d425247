"""relacc's shipped models and scenes, installed as the package data ``relacc.models``.

Read them through :mod:`relacc.fixtures.shipped`; this directory holds no code.
"""
