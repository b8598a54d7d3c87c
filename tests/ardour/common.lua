-- Shared by the Ardour end-to-end scripts (see run.sh): start the dummy backend, open the
-- session, find things, wait for the engine.

SESSION_DIR = assert(os.getenv("PNEUMA_ARDOUR_SESSION"), "PNEUMA_ARDOUR_SESSION not set")
SESSION_NAME = "pneuma"
RATE = 48000

function fail(msg)
  print("ARDOUR CHECK FAILED: " .. msg)
  os.exit(1)
end

function check(ok, msg)
  if not ok then fail(msg) end
end

-- The dummy backend (hidden unless the config sets hide-dummy-backend to 0), 48 kHz, as fast
-- as the machine goes (10x real time; the plugin sees the same blocks either way).
function start_engine()
  local backend = AudioEngine:set_backend("None (Dummy)", "", "")
  check(not backend:isnil(), "no dummy backend: is hide-dummy-backend 0 in the config?")
  backend:set_driver("10x Speed")
  backend:set_sample_rate(RATE)
  check(AudioEngine:start(false) == 0, "the dummy backend does not start")
end

function open_session()
  load_session(SESSION_DIR, SESSION_NAME)
  check(Session ~= nil, "cannot open the session in " .. SESSION_DIR)
end

-- Closes the session. Lua must hold no route or processor of it any more (a reference freed
-- after the session is gone crashes Ardour): scripts keep them in locals of a function that
-- has returned.
function close()
  collectgarbage()
  close_session()
end

function save()
  Session:save_state("", false, false, false, false, false)
end

function sleep_s(s)
  ARDOUR.LuaAPI.usleep(math.floor(s * 1e6))
end

function track(name)
  local r = Session:route_by_name(name)
  check(not r:isnil(), "no track " .. name)
  return r:to_track()
end

-- Polls `done()` every 10 ms until it holds or `timeout_s` has passed (the caller checks the
-- outcome); returns the time waited, microseconds.
function wait_until(timeout_s, done)
  local t0 = ARDOUR.LuaAPI.monotonic_time()
  while not done() and ARDOUR.LuaAPI.monotonic_time() - t0 < timeout_s * 1e6 do
    sleep_s(0.01)
  end
  return ARDOUR.LuaAPI.monotonic_time() - t0
end

-- Waits (up to 10 s) until track `t` holds a region: Ardour's butler thread makes a take's
-- region after the transport stops, so a fixed wait could read the playlist too early.
function wait_for_region(t)
  wait_until(10, function()
    for _ in t:playlist():region_list():iter() do return true end
    return false
  end)
end

function only_region(t)
  local found
  for r in t:playlist():region_list():iter() do
    check(found == nil, "more than one region on " .. t:name())
    found = r
  end
  check(found ~= nil, "no region on " .. t:name())
  return found
end

-- Pneuma's parameter index in Ardour's list, by its display name.
function param_index(proc, label)
  local plugin = proc:to_insert():plugin(0)
  for i = 0, plugin:parameter_count() - 1 do
    if plugin:parameter_label(i) == label then return i end
  end
  fail("Pneuma has no parameter " .. label)
end

-- Rolls from 0 until the transport passes `end_sample`, then stops.
function roll_to(end_sample)
  Session:request_locate(0, false, ARDOUR.LocateTransportDisposition.MustStop,
    ARDOUR.TransportRequestSource.TRS_UI)
  sleep_s(0.3)
  Session:request_roll(ARDOUR.TransportRequestSource.TRS_UI)
  local t0 = ARDOUR.LuaAPI.monotonic_time()
  while Session:transport_sample() < end_sample do
    check(ARDOUR.LuaAPI.monotonic_time() - t0 < 120e6, "the transport did not roll")
    sleep_s(0.01)
  end
  Session:request_stop(false, false, ARDOUR.TransportRequestSource.TRS_UI)
  sleep_s(0.5)
end
