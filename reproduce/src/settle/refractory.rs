//! The refractory state, off and on (§2: it "assures that a signal will neither 'flood' a
//! swarm … nor periodically propagate through the swarm"). The protocol refuses a refractory
//! time not above the relay delay (`ParamError::RefractoryNotAboveRelayDelay`), so below it
//! the wave is run by [`swarm_sim::probe::flood`], the simulator's delivery rule as a model;
//! where the protocol takes the time, the model's wave is checked to be the protocol's.

use crate::Error;
use crate::results::{RefractoryRun, RefractoryRuns};
use crate::stage::Stage;
use crate::stages::WAVE;
use swarm_sim::probe::flood;
use swarm_sim::waves::{Wave, WaveSpec, one_wave};

/// Refractory times tried, seconds (the paper's figure: 10).
pub const REFRACTORY: [u64; 6] = [0, 1, 2, 3, 5, 10];
/// Seconds followed after the initiation.
pub const HORIZON: u64 = 120;
/// Runs each refractory time on the swarm of the paper's Fig. 2.
///
/// # Errors
/// If a wave cannot be run, or the model differs from the protocol where both run.
pub fn runs(st: &mut Stage<'_>) -> Result<RefractoryRuns, Error> {
    let p = st.start("refractory time, off and on", REFRACTORY.len() as u64);
    let seed = st.seed(WAVE.at(0));
    let paper = one_wave(&WaveSpec::paper(), seed)?;
    let relay_s = WaveSpec::paper()
        .config()
        .params
        .wave
        .relay_delay
        .as_millis()
        / 1000;
    let mut runs = Vec::new();
    for refractory_s in REFRACTORY {
        let spec = WaveSpec {
            refractory_s,
            ..WaveSpec::paper()
        };
        let (answer, once) = protocol_answer(&spec, seed, relay_s)?;
        let sends = flood(
            &paper.swarm,
            paper.initiator,
            relay_s,
            refractory_s,
            HORIZON,
        );
        runs.push(RefractoryRun {
            refractory_s,
            answer,
            once,
            sends,
        });
        p.inc();
    }
    st.done(&p);
    Ok(RefractoryRuns {
        agents: paper.len(),
        relay_s,
        runs,
    })
}

/// What the protocol does with `spec`'s refractory time: refuses it (with its error), or runs
/// the wave (checked against the model); with whether every agent sent exactly once.
pub fn protocol_answer(
    spec: &WaveSpec,
    seed: u64,
    relay_s: u64,
) -> Result<(String, Option<bool>), Error> {
    if let Err(e) = spec.config().params.validate() {
        return Ok((format!("refuses it: \"{e}\""), None));
    }
    let w = one_wave(spec, seed)?;
    check(&w, relay_s, spec.refractory_s)?;
    // `one_wave` keeps only waves in which no agent sends twice.
    let once = w.reached() == w.len();
    Ok((
        format!(
            "runs it: {} of {} agents send, each once; the swarm is quiet again at t = {} s",
            w.reached(),
            w.len(),
            w.end_s()
        ),
        Some(once),
    ))
}

/// The model's wave on `w`'s swarm is the protocol's: the same agents send in the same seconds.
pub fn check(w: &Wave, relay_s: u64, refractory_s: u64) -> Result<(), Error> {
    let horizon = w.end_s();
    let sends = flood(&w.swarm, w.initiator, relay_s, refractory_s, horizon);
    let mut expected = vec![0u32; horizon as usize + 1];
    for &t in w.sent_at.iter().flatten() {
        if let Some(e) = expected.get_mut(t as usize) {
            *e += 1;
        }
    }
    if sends != expected {
        return Err(Error::ModelDiffers(refractory_s));
    }
    Ok(())
}
