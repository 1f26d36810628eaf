const _: () = {
    #[automatically_derived]
    impl ::ulog_core::ULogTopics for Topics {
        const NAMES: &'static [&'static str] = &[
            <VehicleAttitude as ::ulog_core::ULogMessage>::NAME,
            <EscStatus as ::ulog_core::ULogMessage>::NAME,
        ];
        const ALIASES: &'static [&'static [&'static str]] = &[
            <VehicleAttitude as ::ulog_core::ULogMessage>::ALIASES,
            <EscStatus as ::ulog_core::ULogMessage>::ALIASES,
        ];
        fn plan(
            variant: usize,
            layout: &::ulog_core::typed::__private::Layout,
        ) -> ::core::option::Option<
            ::core::result::Result<
                ::ulog_core::typed::TopicPlan,
                ::ulog_core::typed::Mismatch,
            >,
        > {
            match variant {
                0usize => {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::TopicPlan::new::<
                            VehicleAttitude,
                        >(0usize, layout),
                    )
                }
                1usize => {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::TopicPlan::new::<EscStatus>(1usize, layout),
                    )
                }
                _ => ::core::option::Option::None,
            }
        }
        fn decode(
            plan: &::ulog_core::typed::TopicPlan,
            payload: &[u8],
        ) -> ::core::result::Result<Self, ::ulog_core::typed::DecodeError> {
            match plan.variant() {
                0usize => {
                    ::core::result::Result::map(
                        plan.decode_as::<VehicleAttitude>(payload),
                        Self::Attitude,
                    )
                }
                1usize => {
                    ::core::result::Result::map(
                        plan.decode_as::<EscStatus>(payload),
                        Self::Esc,
                    )
                }
                variant => {
                    ::core::result::Result::Err(::ulog_core::typed::DecodeError {
                        kind: ::ulog_core::typed::DecodeErrorKind::NoSuchVariant {
                            variant,
                        },
                        len: payload.len(),
                    })
                }
            }
        }
    }
};
