//! The CLAP remote-control pages (a layout for hardware controllers), derived from the
//! parameters rather than listed: one page per group of core's settings table (the unit a host
//! files a parameter under, [`super::unit_of`]), in the parameters' order, at most
//! [`PAGE_SIZE`] to a page (a longer group goes on over "Name 2", "Name 3"); the host's bypass
//! switch is left out.

use nice_plug::prelude::*;

use super::unit_of;

/// Controls on one CLAP remote-control page.
pub const PAGE_SIZE: usize = 8;

/// The parameters left off the pages: the host's own bypass switch.
const LEFT_OUT: [&str; 1] = ["bypass"];

/// The pages of `params`: (name, parameter ids and pointers), in order.
pub fn pages(params: &impl Params) -> Vec<(String, Vec<(String, ParamPtr)>)> {
    let mut groups: Vec<(&'static str, Vec<(String, ParamPtr)>)> = Vec::new();
    for (id, ptr, _) in params.param_map() {
        if LEFT_OUT.contains(&id.as_str()) {
            continue;
        }
        let unit = unit_of(&id);
        match groups.iter_mut().find(|(u, _)| *u == unit) {
            Some((_, members)) => members.push((id, ptr)),
            None => groups.push((unit, vec![(id, ptr)])),
        }
    }
    let mut pages = Vec::new();
    for (unit, members) in groups {
        for (k, chunk) in members.chunks(PAGE_SIZE).enumerate() {
            let name = if k == 0 {
                unit.to_owned()
            } else {
                format!("{unit} {}", k + 1)
            };
            pages.push((name, chunk.to_vec()));
        }
    }
    pages
}

/// Puts the parameter `ptr` on `page`.
#[allow(unsafe_code)]
pub fn add(page: &mut impl RemoteControlsPage, ptr: ParamPtr) {
    // SAFETY: `ptr` comes from `param_map` of the plugin's own parameters, which the plugin
    // holds (in an `Arc`) for as long as the host may call it; nice-plug's wrappers dereference
    // the same pointers the same way.
    unsafe {
        match ptr {
            ParamPtr::FloatParam(p) => page.add_param(&*p),
            ParamPtr::IntParam(p) => page.add_param(&*p),
            ParamPtr::BoolParam(p) => page.add_param(&*p),
            ParamPtr::EnumParam(p) => page.add_param(&*p),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::PneumaParams;

    #[test]
    fn every_parameter_but_bypass_is_on_one_page_of_its_own_group() {
        let params = PneumaParams::default();
        let pages = pages(&params);
        let mut on_pages: Vec<String> = Vec::new();
        for (name, members) in &pages {
            assert!(!members.is_empty() && members.len() <= PAGE_SIZE, "{name}");
            for (id, _) in members {
                assert!(
                    name == unit_of(id) || name.starts_with(&format!("{} ", unit_of(id))),
                    "{id} ({}) on page {name}",
                    unit_of(id)
                );
                on_pages.push(id.clone());
            }
        }
        let mut all: Vec<String> = params
            .param_map()
            .into_iter()
            .map(|(id, _, _)| id)
            .filter(|id| id != "bypass")
            .collect();
        assert_eq!(
            on_pages, all,
            "every parameter once, in the parameters' order"
        );
        all.sort();
        all.dedup();
        assert_eq!(all.len(), on_pages.len());
        // Page names are unique, so a controller can tell them apart.
        let mut names: Vec<&String> = pages.iter().map(|(n, _)| n).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), pages.len());
    }
}
