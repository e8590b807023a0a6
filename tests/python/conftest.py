"""Options of the Python module's tests: the CLI to compare with and the bundled scenes."""
import os

import pytest


def pytest_addoption(parser):
    parser.addoption("--pgt", required=True, help="the pgt executable")
    parser.addoption("--scenes", required=True, help="the bundled scenes folder")


@pytest.fixture(scope="session")
def pgt_cli(request):
    return request.config.getoption("--pgt")


@pytest.fixture(scope="session")
def scenes(request):
    return os.path.abspath(request.config.getoption("--scenes"))
