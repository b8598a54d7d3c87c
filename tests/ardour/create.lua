-- Step 1: a new session with a mono audio track "Voice" holding one region. Lua in Ardour 7
-- cannot import a file, so 2 s are recorded (the dummy backend's silence); run.sh then puts
-- the voice into the recorded file and record.lua stretches the region over it.
dofile(os.getenv("PNEUMA_ARDOUR_SCRIPTS") .. "/common.lua")
start_engine()
local function create()
  create_session(SESSION_DIR, SESSION_NAME, RATE)
  check(Session ~= nil, "cannot create a session in " .. SESSION_DIR)
  Session:new_audio_track(1, 2, nil, 1, "Voice", ARDOUR.PresentationInfo.max_order,
    ARDOUR.TrackMode.Normal, true)
  local voice = track("Voice")
  voice:rec_enable_control():set_value(1, PBD.GroupControlDisposition.NoGroup)
  Session:maybe_enable_record(false)
  roll_to(2 * RATE)
  Session:disable_record(false, false)
  voice:rec_enable_control():set_value(0, PBD.GroupControlDisposition.NoGroup)
  wait_for_region(voice)
  local region = only_region(voice)
  print("recorded region " .. region:name() .. " of " .. region:length():samples() .. " samples")
  save()
end

create()
close()
print("DONE")
