"""Settings of the test session: the user's store of settled fences is off (WIRENET_CACHE=off),
so that every test's fence settles as the test says and no test depends on what an earlier run
on this machine left; the tests of the store set their own folder."""

import os

os.environ["WIRENET_CACHE"] = "off"
