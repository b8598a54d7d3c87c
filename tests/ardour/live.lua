-- Step 3 (after the export): Mode = Live takes effect in the open session (latency 0, no
-- reload), a session saved as soon as parameter changes have reached the plugin reopens with
-- them, in Live mode.
-- Appends to $PNEUMA_ARDOUR_OUT/facts.txt.
dofile(os.getenv("PNEUMA_ARDOUR_SCRIPTS") .. "/common.lua")
local out_dir = assert(os.getenv("PNEUMA_ARDOUR_OUT"), "PNEUMA_ARDOUR_OUT not set")
start_engine()
local facts = io.open(out_dir .. "/facts.txt", "a")

local function change_and_save()
  open_session()
  local voice = track("Voice")
  local pneuma = voice:nth_plugin(0)
  check(not pneuma:isnil(), "Pneuma is gone from the voice track")
  local mode = param_index(pneuma, "Mode")
  local level = param_index(pneuma, "Breath level")
  sleep_s(0.2)
  facts:write("reopened_latency_samples=" .. pneuma:signal_latency() .. "\n")

  -- A host-side change reaches a VST3 plugin with its next process block: while the engine
  -- runs, nice-plug's VST3 controller leaves setParamNormalized to the block's parameter
  -- queue, and Ardour writes the plugin's state chunk (which wins on reopen) at once. A save
  -- before that block keeps the old value (in the CI run of 1d7b55c, -22 dB came back).
  -- So the level goes first, into the same queue as Mode, and the wait below for Mode's
  -- latency proves the block carrying both has run.
  ARDOUR.LuaAPI.set_processor_param(pneuma, level, -10)
  ARDOUR.LuaAPI.set_processor_param(pneuma, mode, 1)
  -- The plugin builds the live engine in the background and reports its latency.
  local waited = wait_until(5, function()
    return pneuma:signal_latency() == 0 and voice:signal_latency() == 0
  end)
  facts:write("live_latency_samples=" .. pneuma:signal_latency() .. "\n")
  facts:write("live_after_ms=" .. math.floor(waited / 1000) .. "\n")
  facts:write("live_route_latency_samples=" .. voice:signal_latency() .. "\n")
  -- Saved at once: the state must hold both changes.
  save()
end

local function reopen()
  open_session()
  local voice = track("Voice")
  local pneuma = voice:nth_plugin(0)
  local mode = param_index(pneuma, "Mode")
  local level = param_index(pneuma, "Breath level")
  -- Restored in Live mode, the plugin builds its live engine in the background as above.
  wait_until(5, function() return pneuma:signal_latency() == 0 end)
  facts:write("reopened_mode=" .. ARDOUR.LuaAPI.get_processor_param(pneuma, mode) .. "\n")
  facts:write("reopened_breath_level_db=" .. ARDOUR.LuaAPI.get_processor_param(pneuma, level) .. "\n")
  facts:write("reopened_live_latency_samples=" .. pneuma:signal_latency() .. "\n")
end

change_and_save()
close()
reopen()
close()
facts:close()
print("DONE")
